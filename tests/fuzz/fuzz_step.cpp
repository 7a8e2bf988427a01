// libFuzzer harness for the real-time path. The input bytes choose a scalar
// type, a controller and its configuration, then a sequence of calls with
// arbitrary states, references and parameters (raw bit patterns included, so
// NaN, Inf, denormals and 1e308 all come up) to:
//   * every controller's step(),
//   * the reference model's step(),
//   * Vehicle::derivative / acceleration and rk4_step with fuzzed parameters,
//   * the thruster allocation,
//   * and, now and then, a short closed loop (simulate) with fuzzed faults.
// It aborts (a libFuzzer crash) when one of the library's promises breaks:
//   * outputs are finite whatever the input;
//   * a call that returns anything but ok writes tau = 0 (controllers) and
//     leaves the object's state bit-for-bit as it was;
//   * an invalid configuration is refused with a named field and the output
//     object left unconfigured.
// AddressSanitizer and UBSan run alongside (see CMakeLists.txt).
//
//   cmake -S . -B build-fuzz -DNEUROV_BUILD_FUZZ=ON -DCMAKE_CXX_COMPILER=clang++
//   cmake --build build-fuzz --target neurov_fuzz_step
//   mkdir -p corpus && build-fuzz/tests/fuzz/neurov_fuzz_step -max_total_time=60 \
//       -max_len=1024 -len_control=0 corpus tests/fuzz/regressions
//   build-fuzz/tests/fuzz/neurov_fuzz_step crash-<hash>     # replay a crash
// A crash, once fixed, joins tests/fuzz/regressions under the defect's name.
// (-len_control=0: a controller step needs ~150 input bytes, which libFuzzer's
// slow growth of the input length would take most of a minute to reach.)
#include <fuzzer/FuzzedDataProvider.h>

#include <cstddef>
#include <cstdint>

namespace neurov_fuzz {
template <typename S>
void fuzz_one(FuzzedDataProvider& p);
extern template void fuzz_one<float>(FuzzedDataProvider&);
extern template void fuzz_one<double>(FuzzedDataProvider&);
}  // namespace neurov_fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider p(data, size);
  if (p.ConsumeBool())
    neurov_fuzz::fuzz_one<float>(p);
  else
    neurov_fuzz::fuzz_one<double>(p);
  return 0;
}
