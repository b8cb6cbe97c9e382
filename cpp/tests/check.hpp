// The one check macro of the C++ tests: a failed check prints its file, line and condition and
// counts; each test's main returns `failures != 0`.
#pragma once

#include <iostream>

inline int failures = 0;

#define CHECK(cond)                                                                      \
    do {                                                                                 \
        if (!(cond)) {                                                                   \
            std::cerr << __FILE__ << ":" << __LINE__ << ": check failed: " #cond "\n";   \
            ++failures;                                                                  \
        }                                                                                \
    } while (0)
