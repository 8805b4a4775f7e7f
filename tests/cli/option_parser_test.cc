// OptionParser: the COLMAP-style "--Section.name value" options of every colmap-mp command.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "colmap_ext/cli/option_parser.h"
#include "colmap_ext/util/error.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

struct Fields {
  bool flag = true;
  int count = 3;
  double scale = 0.5;
  std::string name = "plain";
  std::string path;
};

// A parser over f like a command's: one field of each type, one required, one ignored.
OptionParser MakeParser(Fields* f) {
  OptionParser parser;
  parser.Add("Section.flag", &f->flag, "a switch");
  parser.Add("Section.count", &f->count, "a count");
  parser.Add("Section.scale", &f->scale, "a factor");
  parser.Add("name", &f->name, "a word");
  parser.AddRequired("path", &f->path, "a folder");
  parser.AddIgnored("Section.window_radius", "use --Section.scale");
  return parser;
}

// The message of the Error Parse throws, "" when it throws none.
std::string ParseError(const std::vector<std::string>& args) {
  Fields f;
  OptionParser parser = MakeParser(&f);
  try {
    parser.Parse(args);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(OptionParser, SetsEveryTypeFromNameValuePairs) {
  Fields f;
  OptionParser parser = MakeParser(&f);
  ASSERT_TRUE(parser.Parse({"--path", "/data/ws", "--Section.flag", "0", "--Section.count", "-7",
                            "--Section.scale", "-1.25e-1", "--name", "two words"}));
  EXPECT_FALSE(f.flag);
  EXPECT_EQ(f.count, -7);
  EXPECT_EQ(f.scale, -0.125);
  EXPECT_EQ(f.name, "two words");
  EXPECT_EQ(f.path, "/data/ws");
  EXPECT_TRUE(parser.Warnings().empty());
}

TEST(OptionParser, AcceptsNameEqualsValue) {
  Fields f;
  OptionParser parser = MakeParser(&f);
  ASSERT_TRUE(parser.Parse({"--path=/a=b", "--Section.count=12", "--Section.scale=-2"}));
  EXPECT_EQ(f.path, "/a=b");  // split at the first '='
  EXPECT_EQ(f.count, 12);
  EXPECT_EQ(f.scale, -2.0);
}

TEST(OptionParser, KeepsDefaultsOfOptionsNotGiven) {
  Fields f;
  OptionParser parser = MakeParser(&f);
  ASSERT_TRUE(parser.Parse({"--path", "p"}));
  EXPECT_TRUE(f.flag);
  EXPECT_EQ(f.count, 3);
  EXPECT_EQ(f.scale, 0.5);
  EXPECT_EQ(f.name, "plain");
}

TEST(OptionParser, BooleansLikeColmap) {
  for (const auto& [text, expected] : std::vector<std::pair<std::string, bool>>{
           {"1", true}, {"true", true}, {"TRUE", true}, {"True", true}, {"yes", true}, {"On", true},
           {"0", false}, {"false", false}, {"FaLsE", false}, {"no", false}, {"OFF", false}}) {
    bool value = !expected;
    EXPECT_TRUE(ParseBool(text, &value)) << text;
    EXPECT_EQ(value, expected) << text;
  }
  for (const char* text : {"", "y", "n", "of", "2", "-1", "truee"}) {
    bool value = true;
    EXPECT_FALSE(ParseBool(text, &value)) << text;
    EXPECT_TRUE(value) << text;
  }
  EXPECT_EQ(ParseError({"--path", "p", "--Section.flag", "y"}), "bad value 'y' for option --Section.flag");
  Fields f;
  OptionParser parser = MakeParser(&f);
  ASSERT_TRUE(parser.Parse({"--path", "p", "--Section.flag", "off"}));
  EXPECT_FALSE(f.flag);
}

TEST(OptionParser, BadNumbersNameTheOption) {
  for (const char* bad : {"1.5", "x", "", "99999999999", "3 "}) {
    EXPECT_EQ(ParseError({"--path", "p", "--Section.count", bad}),
              "bad value '" + std::string(bad) + "' for option --Section.count");
  }
  for (const char* bad : {"nan", "inf", "1e999", "0.5x"}) {
    EXPECT_EQ(ParseError({"--path", "p", "--Section.scale", bad}),
              "bad value '" + std::string(bad) + "' for option --Section.scale");
  }
}

TEST(OptionParser, ListsOfNumbers) {
  std::vector<double> list = {0.01, 0.02};
  OptionParser parser;
  parser.Add("tolerances", &list, "a list");
  EXPECT_NE(parser.Help().find("0.01,0.02"), std::string::npos) << parser.Help();
  ASSERT_TRUE(parser.Parse({"--tolerances", "0.005,1e-2,0.05"}));
  EXPECT_EQ(list, (std::vector<double>{0.005, 0.01, 0.05}));
  ASSERT_TRUE(parser.Parse({"--tolerances", " 0.01 , 0.02,"}));  // as SplitList reads --workspace_paths
  EXPECT_EQ(list, (std::vector<double>{0.01, 0.02}));
  ASSERT_TRUE(parser.Parse({"--tolerances=0.2"}));
  EXPECT_EQ(list, (std::vector<double>{0.2}));
  for (const char* bad : {"", ",", " , ", "0.01;0.02", "0.01,x", "0.01,nan", "0.01,2 3"}) {
    try {
      parser.Parse({"--tolerances", bad});
      ADD_FAILURE() << "no error for '" << bad << "'";
    } catch (const Error& error) {
      EXPECT_EQ(std::string(error.what()), "bad value '" + std::string(bad) + "' for option --tolerances");
    }
    EXPECT_EQ(list, (std::vector<double>{0.2}));  // unchanged
  }
}

TEST(OptionParser, UnknownOptionListsTheValidOnes) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--path", "p", "--Section.bogus", "1"},
        std::vector<std::string>{"--Section.bogus=1", "--path", "p"}}) {
    const std::string error = ParseError(args);
    EXPECT_EQ(error.rfind("unknown option --Section.bogus. Valid options:", 0), 0u) << error;
    EXPECT_NE(error.find("\n  --Section.count"), std::string::npos);
    EXPECT_NE(error.find("\n  --path"), std::string::npos);
    EXPECT_EQ(error.find("window_radius"), std::string::npos);  // ignored ones are not offered
  }
  // Names are exact: no abbreviations, no case folding.
  EXPECT_NE(ParseError({"--path", "p", "--Section.cou", "1"}).find("unknown option --Section.cou."),
            std::string::npos);
  EXPECT_NE(ParseError({"--path", "p", "--section.count", "1"}).find("unknown option --section.count."),
            std::string::npos);
}

TEST(OptionParser, MissingValuesAndStrayWords) {
  EXPECT_EQ(ParseError({"--path", "p", "--Section.count"}), "option --Section.count needs a value");
  // As in COLMAP, the word after an option is its value even when it looks like an option.
  EXPECT_EQ(ParseError({"--Section.count", "--path", "p"}), "bad value '--path' for option --Section.count");
  EXPECT_EQ(ParseError({"--path", "p", "--name="}), "option --name needs a value");
  EXPECT_EQ(ParseError({"--path", "p", "stray"}),
            "unexpected argument 'stray' (options are given as --name value)");
  EXPECT_EQ(ParseError({"-path", "p"}),
            "unexpected argument '-path' (options are given as --name value)");
}

TEST(OptionParser, RequiredOptionMustBeGiven) {
  EXPECT_EQ(ParseError({"--Section.count", "1"}), "missing required option --path");
  EXPECT_EQ(ParseError({}), "missing required option --path");
}

TEST(OptionParser, HelpStopsParsing) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"-h"}, std::vector<std::string>{"--help"},
        std::vector<std::string>{"--Section.count", "5", "-h"}}) {
    Fields f;
    OptionParser parser = MakeParser(&f);
    EXPECT_FALSE(parser.Parse(args));  // no "missing required option"
  }
  // "-h" right after an option is that option's value.
  Fields f;
  OptionParser parser = MakeParser(&f);
  EXPECT_TRUE(parser.Parse({"--path", "-h"}));
  EXPECT_EQ(f.path, "-h");
}

TEST(OptionParser, IgnoredOptionsWarnOnce) {
  Fields f;
  OptionParser parser = MakeParser(&f);
  ASSERT_TRUE(parser.Parse({"--Section.window_radius", "7", "--path", "p",
                            "--Section.window_radius", "anything"}));
  ASSERT_EQ(parser.Warnings().size(), 1u);
  EXPECT_EQ(parser.Warnings()[0],
            "--Section.window_radius is accepted for COLMAP compatibility but ignored: use "
            "--Section.scale");
}

TEST(OptionParser, RepeatedOptionWarnsAndTakesTheLastValue) {
  Fields f;
  OptionParser parser = MakeParser(&f);
  ASSERT_TRUE(parser.Parse({"--path", "p", "--Section.count", "1", "--Section.count=2",
                            "--Section.count", "4"}));
  EXPECT_EQ(f.count, 4);
  ASSERT_EQ(parser.Warnings().size(), 1u);
  EXPECT_EQ(parser.Warnings()[0], "--Section.count is given 3 times; the last value is used");
  // Every value is still checked.
  EXPECT_EQ(ParseError({"--path", "p", "--Section.count", "x", "--Section.count", "4"}),
            "bad value 'x' for option --Section.count");
}

// COLMAP's --project_path: INI keys at the top level and under [Section]; the command line
// overrides the file; the file's mistakes name the file.
TEST(OptionParser, ProjectFileIsReadFirstAndTheCommandLineOverridesIt) {
  test::TempDir tmp;
  {
    std::ofstream ini(tmp / "p.ini");
    ini << "# a comment\npath = /from/file\nname = file name\n\n[Section]\nflag = false\ncount = 9\n"
           "scale = 2.5\nwindow_radius = 3\n";
  }
  Fields f;
  std::string project;
  OptionParser parser = MakeParser(&f);
  parser.AddProjectFile("project_path", &project);
  ASSERT_TRUE(parser.Parse({"--Section.count", "4", "--project_path", tmp / "p.ini"}));
  EXPECT_EQ(f.path, "/from/file");  // the required option, from the file
  EXPECT_EQ(f.name, "file name");
  EXPECT_FALSE(f.flag);
  EXPECT_EQ(f.count, 4);  // the command line wins, wherever it stands
  EXPECT_EQ(f.scale, 2.5);
  EXPECT_TRUE(parser.Given("Section.scale"));
  ASSERT_EQ(parser.Warnings().size(), 1u);  // the ignored option, once; no "given twice"
  EXPECT_NE(parser.Warnings()[0].find("--Section.window_radius is accepted"), std::string::npos);

  const auto error = [&](const std::string& text) {
    { std::ofstream(tmp / "bad.ini") << text; }
    Fields g;
    OptionParser p = MakeParser(&g);
    p.AddProjectFile("project_path", &project);
    try {
      p.Parse({"--project_path", tmp / "bad.ini"});
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error("path = p\n[Section]\ncount = x\n"), "bad value 'x' for option --Section.count in " + (tmp / "bad.ini"));
  EXPECT_EQ(error("path = p\n[Other]\ncount = 1\n").rfind("unknown option --Other.count in " + (tmp / "bad.ini") +
                                                         ". Valid options:", 0),
            0u);
  EXPECT_EQ(error("path = p\nproject_path = q.ini\n").rfind("unknown option --project_path in ", 0), 0u);
  EXPECT_EQ(error("[Section]\ncount = 1\n"), "missing required option --path");
  EXPECT_NE(error("path = p\nnot an option line\n").find(tmp / "bad.ini"), std::string::npos);
  Fields h;
  OptionParser p = MakeParser(&h);
  p.AddProjectFile("project_path", &project);
  EXPECT_THROW(p.Parse({"--project_path", tmp / "none.ini"}), Error);
}

TEST(OptionParser, HelpListsNameDefaultAndHelp) {
  Fields f;
  const std::string help = MakeParser(&f).Help();
  for (const char* part : {"--Section.flag 0|1 (=1)", "a switch", "--Section.count int (=3)",
                           "a count", "--Section.scale num (=0.5)", "--name text (=plain)",
                           "--path text", "(required) a folder", "--Section.window_radius any",
                           "ignored by mp-mvs: use --Section.scale"}) {
    EXPECT_NE(help.find(part), std::string::npos) << part << " in\n" << help;
  }
  EXPECT_EQ(help.find("--path text (="), std::string::npos) << help;  // no default shown
}

}  // namespace
}  // namespace mpmvs
