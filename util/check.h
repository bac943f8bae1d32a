// Two kinds of failure, kept apart on purpose:
//  * brdfshot::Error — the user's input is wrong (bad file, bad option). The message
//    names the file and the problem; apps print it and exit non-zero.
//  * BRDFSHOT_CHECK — an internal invariant broke (a bug). Throws std::logic_error
//    with the source location so the report points at the code, not the user.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace brdfshot {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Error about a file: "<path>: <problem>".
inline Error FileError(const std::string& path, const std::string& problem) { return Error(path + ": " + problem); }

namespace internal {
[[noreturn]] inline void CheckFailed(const char* expr, const char* file, int line, const std::string& msg) {
  std::ostringstream s;
  s << "internal check failed: " << expr << " at " << file << ":" << line;
  if (!msg.empty()) s << " (" << msg << ")";
  throw std::logic_error(s.str());
}
}  // namespace internal

}  // namespace brdfshot

#define BRDFSHOT_CHECK(cond, ...)                                                              \
  do {                                                                                         \
    if (!(cond)) {                                                                             \
      std::ostringstream brdfshot_check_msg_;                                                  \
      brdfshot_check_msg_ << "" __VA_ARGS__;                                                   \
      ::brdfshot::internal::CheckFailed(#cond, __FILE__, __LINE__, brdfshot_check_msg_.str()); \
    }                                                                                          \
  } while (0)
