// The multi-view room family of synthetic scenes: defaults, geometry and GT, untextured
// share, deterministic rendering, and sparse points from COLMAP's SIFT (skipped with a
// message when the colmap executable is missing).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "colmap_ext/synthetic/synthetic_layouts.h"
#include "colmap_ext/synthetic/synthetic_scene.h"
#include "colmap_ext/util/colmap_runner.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

// A room at reduced size without COLMAP: for checks of geometry and photometry.
SyntheticSceneOptions SmallRoom(const std::string& scene) {
  SyntheticSceneOptions o = SyntheticSceneOptions::ForScene(scene);
  o.width = 160;
  o.height = 120;
  o.supersampling = 1;
  o.sparse_source = "simulated";
  return o;
}

std::vector<std::string> FilesUnder(const std::string& dir) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) files.push_back(std::filesystem::relative(e.path(), dir).string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(SyntheticRooms, NamesAndDefaults) {
  const std::vector<std::string> names = SyntheticSceneNames();
  const std::vector<std::string> rooms = SyntheticRoomSceneNames();
  ASSERT_GE(rooms.size(), 3u);
  for (const std::string& room : rooms) {
    EXPECT_NE(std::find(names.begin(), names.end(), room), names.end()) << room;
    const SyntheticSceneOptions o = SyntheticSceneOptions::ForScene(room);
    EXPECT_EQ(o.width, 640);
    EXPECT_EQ(o.height, 480);
    EXPECT_GE(o.num_views, 8);
    EXPECT_LE(o.num_views, 12);
    EXPECT_EQ(o.sparse_source, "sift");
    EXPECT_GT(o.noise_sigma, 0);
    o.Check();
  }
  // The frozen scenes keep the old defaults.
  for (const std::string& old : {"indoor", "facade", "plane"}) {
    const SyntheticSceneOptions o = SyntheticSceneOptions::ForScene(old);
    EXPECT_EQ(o.width, 320);
    EXPECT_EQ(o.num_views, 5);
    EXPECT_EQ(o.sparse_source, "simulated");
    EXPECT_EQ(o.vignetting, 0);
    EXPECT_EQ(o.shot_noise, 0);
  }
  SyntheticSceneOptions bad = SyntheticSceneOptions::ForScene("room_l");
  bad.sparse_source = "orb";
  EXPECT_THROW(bad.Check(), Error);
}

TEST(SyntheticRooms, LayoutsAtDefaultSize) {
  for (const std::string& room : SyntheticRoomSceneNames()) {
    const SyntheticSceneOptions o = SyntheticSceneOptions::ForScene(room);
    LayoutParams p;
    p.scene = room;
    p.width = o.width;
    p.height = o.height;
    p.num_views = o.num_views;
    const SyntheticLayout layout = BuildSyntheticLayout(p);
    ASSERT_EQ(static_cast<int>(layout.cameras.size()), o.num_views) << room;
    for (const SyntheticCamera& c : layout.cameras) {
      EXPECT_EQ(c.width, 640);
      EXPECT_EQ(c.height, 480);
      EXPECT_NEAR(c.fx, 512, 1e-9);
      EXPECT_NEAR(c.fy, 512, 2);
      // Inside the room: the ray straight ahead hits a surface within 12 m.
      SceneHit hit;
      EXPECT_TRUE(layout.world.geometry.Intersect(c.RayThrough(c.cx, c.cy), 1e-6, 12, &hit))
          << room;
    }
  }
}

TEST(SyntheticRooms, ClosedRoomsWithLargeUntexturedShare) {
  for (const std::string& room : SyntheticRoomSceneNames()) {
    const SyntheticScene scene = RenderSyntheticScene(SmallRoom(room));
    ASSERT_EQ(static_cast<int>(scene.views.size()), scene.options.num_views);
    const double share = UntexturedShare(scene);
    EXPECT_GE(share, 0.4) << room;
    EXPECT_LE(share, 0.95) << room;  // and textured things to match on
    for (const SyntheticView& v : scene.views) {
      EXPECT_GT(v.stats.untextured_fraction, 0.15) << room << " " << v.name;
      const FloatMap& n = v.render.normal;
      for (int row = 0; row < n.height; ++row) {
        for (int col = 0; col < n.width; ++col) {
          ASSERT_GT(v.render.depth.At(row, col), 0) << room << ": closed rooms have GT everywhere";
          const double norm = std::sqrt(n.At(row, col, 0) * n.At(row, col, 0) +
                                        n.At(row, col, 1) * n.At(row, col, 1) +
                                        n.At(row, col, 2) * n.At(row, col, 2));
          ASSERT_NEAR(norm, 1.0, 1e-4) << room << " " << v.name;
          const SyntheticCamera& c = v.camera;
          const double facing = n.At(row, col, 0) * (col - c.cx) / c.fx +
                                n.At(row, col, 1) * (row - c.cy) / c.fy + n.At(row, col, 2);
          ASSERT_LT(facing, 0) << room << ": normals face the camera";
        }
      }
    }
  }
}

TEST(SyntheticRooms, ShellSurfacesAreNamed) {
  for (const std::string& room : SyntheticRoomSceneNames()) {
    SyntheticSceneOptions o = SmallRoom(room);
    o.num_views = 4;
    const SyntheticScene scene = RenderSyntheticScene(o);
    const std::vector<std::string>& names = scene.surface_names;
    for (const char* part : {"ceiling", "floor"}) {
      EXPECT_NE(std::find(names.begin(), names.end(), part), names.end()) << room << " " << part;
    }
    for (const SyntheticView& v : scene.views) {
      size_t named = 0;
      for (uint8_t label : v.render.surface) {
        ASSERT_LE(label, names.size()) << room;
        named += label > 0;
      }
      // The shell is most of what a camera inside a room sees.
      EXPECT_GT(named, v.render.surface.size() / 3) << room << " " << v.name;
    }
  }
}

TEST(SyntheticRooms, SweepSeesSideWallsAtGrazingAnglesAndASaturatedCeilingLight) {
  const SyntheticScene scene = RenderSyntheticScene(SmallRoom("room_sweep"));
  const std::vector<std::string>& names = scene.surface_names;
  const auto label_of = [&](const std::string& name) {
    return static_cast<uint8_t>(std::find(names.begin(), names.end(), name) - names.begin() + 1);
  };
  const uint8_t side = label_of("side walls"), far = label_of("far wall"), ceiling = label_of("ceiling");
  ASSERT_LE(side, names.size());
  ASSERT_LE(ceiling, names.size());
  size_t side_pixels = 0, grazing = 0, far_pixels = 0, far_head_on = 0, saturated_ceiling = 0;
  for (const SyntheticView& v : scene.views) {
    const SyntheticCamera& c = v.camera;
    for (int row = 0; row < c.height; ++row) {
      for (int col = 0; col < c.width; ++col) {
        const size_t i = static_cast<size_t>(row) * c.width + col;
        const Eigen::Vector3d ray = Eigen::Vector3d((col - c.cx) / c.fx, (row - c.cy) / c.fy, 1).normalized();
        const Eigen::Vector3d n(v.render.normal.At(row, col, 0), v.render.normal.At(row, col, 1),
                                v.render.normal.At(row, col, 2));
        const double incidence = std::acos(std::min(1.0, std::abs(ray.dot(n)))) * 180 / M_PI;
        if (v.render.surface[i] == side) {
          ++side_pixels;
          grazing += incidence >= 60;
        } else if (v.render.surface[i] == far) {
          ++far_pixels;
          far_head_on += incidence <= 40;
        } else if (v.render.surface[i] == ceiling) {
          const uint8_t* rgb = &v.render.image.data[3 * i];
          saturated_ceiling += rgb[0] == 255 && rgb[1] == 255 && rgb[2] == 255;
        }
      }
    }
  }
  EXPECT_GT(side_pixels, scene.views.size() * 160 * 120 / 10);
  EXPECT_GT(grazing, 0.8 * side_pixels);
  EXPECT_GT(far_head_on, 0.9 * far_pixels);
  EXPECT_GT(saturated_ceiling, 20u);
}

TEST(SyntheticRooms, WindowIsBrightAndUntextured) {
  const SyntheticScene scene = RenderSyntheticScene(SmallRoom("room_window"));
  size_t bright = 0, bright_untextured = 0;
  for (const SyntheticView& v : scene.views) {
    for (size_t i = 0; i < v.render.untextured.size(); ++i) {
      const uint8_t* rgb = &v.render.image.data[3 * i];
      if (rgb[0] >= 240 && rgb[1] >= 240 && rgb[2] >= 240) {
        ++bright;
        bright_untextured += v.render.untextured[i] != 0;
      }
    }
  }
  EXPECT_GT(bright, 1000u);
  EXPECT_GT(bright_untextured, 0.9 * bright);
}

TEST(SyntheticRooms, GenerationIsDeterministic) {
  const test::TempDir temp;
  const std::string dir = temp.path();
  SyntheticSceneOptions o = SmallRoom("room_corridor");
  o.num_views = 8;
  GenerateSyntheticScene(o, JoinPaths(dir, "a"));
  GenerateSyntheticScene(o, JoinPaths(dir, "b"));
  const std::vector<std::string> files = FilesUnder(JoinPaths(dir, "a"));
  ASSERT_EQ(files, FilesUnder(JoinPaths(dir, "b")));
  ASSERT_GT(files.size(), 40u);
  EXPECT_NE(std::find(files.begin(), files.end(), "gt/surface_view_00.png"), files.end());
  const std::string names = "walls\nceiling\nfloor\n";
  EXPECT_EQ(ReadFileBytes(JoinPaths(dir, "a/gt/surfaces.txt")), std::vector<uint8_t>(names.begin(), names.end()));
  for (const std::string& f : files) {
    EXPECT_EQ(ReadFileBytes(JoinPaths(dir, "a/" + f)), ReadFileBytes(JoinPaths(dir, "b/" + f))) << f;
  }
}

TEST(SyntheticRooms, SiftSparsePointsComeFromMatching) {
  if (!ColmapAvailable()) GTEST_SKIP() << "colmap executable not found: SIFT sparse path not tested";
  const test::TempDir temp;
  const std::string dir = temp.path();
  SyntheticSceneOptions o = SyntheticSceneOptions::ForScene("room_window");
  o.width = 320;
  o.height = 240;
  o.num_views = 8;
  o.supersampling = 1;
  const SyntheticScene scene = GenerateSyntheticScene(o, dir);
  const SparseModel model = ReadSparseModel(JoinPaths(dir, "sparse"));
  ASSERT_EQ(model.images.size(), 8u);
  ASSERT_EQ(model.cameras.size(), 1u);
  const SyntheticCamera& c = scene.views[0].camera;
  EXPECT_EQ(model.cameras[0].params, (std::vector<double>{c.fx, c.fy, c.cx, c.cy}));
  for (size_t v = 0; v < model.images.size(); ++v) {
    EXPECT_EQ(model.images[v].image_id, v + 1);
    EXPECT_EQ(model.images[v].name, scene.views[v].name);
  }
  const SparsePointLabels& l = scene.sparse_labels;
  const int total = l.on_textured + l.on_untextured + l.off_surface;
  ASSERT_EQ(total, static_cast<int>(model.points.size()));
  EXPECT_GE(total, 30);
  // Matching finds its points on the textured objects; plain walls/ceiling get few
  // (window-frame corners), although they fill most of the images.
  EXPECT_GT(l.on_textured, 2 * l.on_untextured);
  EXPECT_LT(l.on_untextured, 0.35 * total);
  EXPECT_LT(l.off_surface, 0.2 * total);
  for (const SparsePoint3D& p : model.points) ASSERT_GE(p.track.size(), 2u);
}

TEST(SyntheticRooms, MissingColmapIsAClearError) {
  const char* old = std::getenv("MPMVS_COLMAP_EXE");
  const std::string saved = old ? old : "";
  setenv("MPMVS_COLMAP_EXE", "/nonexistent/colmap", 1);
  SyntheticSceneOptions o = SyntheticSceneOptions::ForScene("room_l");
  o.width = 64;
  o.height = 48;
  try {
    RenderSyntheticScene(o);
    ADD_FAILURE() << "expected an Error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("/nonexistent/colmap"), std::string::npos) << message;
    EXPECT_NE(message.find("MPMVS_COLMAP_EXE"), std::string::npos) << message;
    EXPECT_NE(message.find("--sparse_source simulated"), std::string::npos) << message;
  }
  if (old) {
    setenv("MPMVS_COLMAP_EXE", saved.c_str(), 1);
  } else {
    unsetenv("MPMVS_COLMAP_EXE");
  }
}

}  // namespace
}  // namespace mpmvs
