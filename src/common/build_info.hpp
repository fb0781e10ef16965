#pragma once
// What binary produced a result: recorded in summary.json and the bench JSON so that numbers
// in a paper can be traced back to a version, compiler and flags.
#include <string>

namespace settle {

struct BuildInfo {
  std::string version;
  std::string compiler;
  std::string build_type;
  bool native_cpu;  ///< built with -march=native
  bool sanitizers;  ///< built with ASan/UBSan (timings then mean nothing)
};

BuildInfo build_info();

}  // namespace settle
