// libFuzzer's entry point for the target named by MESHFIT_FUZZ_TARGET_NAME.
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const meshfit_fuzz::Target target = meshfit_fuzz::registry().at(MESHFIT_FUZZ_TARGET_NAME);
  return target(data, size);
}
