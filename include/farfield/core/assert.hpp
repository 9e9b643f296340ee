// FF_ASSERT: checks a programming invariant in every build type. On failure it prints the
// function, the condition and a message, then aborts. Never used for bad user input.
#pragma once

#include <cstdio>
#include <cstdlib>

#define FF_ASSERT(condition, ...)                                                        \
  do {                                                                                   \
    if (!(condition)) {                                                                  \
      std::fprintf(stderr, "farfield: assertion failed in %s: %s: ", __func__, #condition); \
      std::fprintf(stderr, __VA_ARGS__);                                                 \
      std::fputc('\n', stderr);                                                          \
      std::abort();                                                                      \
    }                                                                                    \
  } while (false)
