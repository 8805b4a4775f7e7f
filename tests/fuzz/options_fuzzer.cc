// libFuzzer harness of the options reader (entry point in fuzz_readers.cc).
#include "tests/fuzz/fuzz_readers.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const mpmvs::fuzz::FuzzReader& reader = mpmvs::fuzz::FindFuzzReader("options");
  return mpmvs::fuzz::RunFuzzReader(reader, data, size);
}
