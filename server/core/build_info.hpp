#pragma once
// What this binary is: version, commit, compiler and the versions of the libraries it was built with,
// so that a stored result can be traced to the exact code that produced it.
#include <string>

namespace hrisim::core {

/// Semantic version of hrisim (from CMakeLists.txt).
const char* version();
/// Git commit the binary was built from, with "-dirty" when the tree had uncommitted changes.
const char* git_commit();
/// CMake build type (Release, RelWithDebInfo, ...).
const char* build_type();
/// Compiler name and version, e.g. "GCC 12.2.0".
std::string compiler();
/// Eigen version the core was compiled against, e.g. "3.4.0".
std::string eigen_version();
/// nlohmann-json version, e.g. "3.11.2".
std::string json_version();

}  // namespace hrisim::core
