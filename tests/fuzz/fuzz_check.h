#pragma once
// What the fuzz targets share: an invariant check that stops the fuzzer (a crash it saves and reports), and the
// rule every rejected input must follow: the error names the input's source, so a user knows which file is wrong.

#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#define FUZZ_CHECK(condition, ...)                                                           \
  do {                                                                                       \
    if (!(condition)) {                                                                      \
      std::fprintf(stderr, "%s:%d: invariant broken: %s\n", __FILE__, __LINE__, #condition); \
      __VA_OPT__(std::fprintf(stderr, __VA_ARGS__);)                                         \
      std::fprintf(stderr, "\n");                                                            \
      std::abort();                                                                          \
    }                                                                                        \
  } while (false)

namespace softwrist::fuzz {

// An error message must start with the source it names (the file, or the option) and say more than that.
inline void check_names_source(const std::string& message, std::string_view source) {
  FUZZ_CHECK(message.rfind(source, 0) == 0 && message.size() > source.size() + 2, "message: %s", message.c_str());
}

}  // namespace softwrist::fuzz
