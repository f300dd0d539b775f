// What the fuzz targets share.
#pragma once

#include <cstdlib>

namespace toolpoint::fuzz {

// A broken rule of the code under test: abort, which libFuzzer reports as a crash with the input.
inline void require(bool rule) {
  if (!rule) std::abort();
}

}  // namespace toolpoint::fuzz
