#include "common/build_info.hpp"

#include "settle/version.hpp"

namespace settle {

BuildInfo build_info() {
  BuildInfo info;
  info.version = version_string;
#if defined(__clang__)
  info.compiler = "clang " __clang_version__;
#elif defined(__GNUC__)
  info.compiler = "gcc " __VERSION__;
#else
  info.compiler = "unknown";
#endif
  info.build_type = SETTLE_BUILD_TYPE;
#ifdef SETTLE_NATIVE_BUILD
  info.native_cpu = true;
#else
  info.native_cpu = false;
#endif
#ifdef SETTLE_SANITIZE_BUILD
  info.sanitizers = true;
#else
  info.sanitizers = false;
#endif
  return info;
}

}  // namespace settle
