// The example assembly's tool point modes for the stability benchmarks: 4 modes per direction
// fitted to the example's tool point FRF (`toolpoint modes`), as issue 16's command used them.
#pragma once

#include <vector>

#include "toolpoint/stability/modal_fit.hpp"

namespace toolpoint::bench {

inline std::vector<Mode> example_modes() {
  return {{0.576061, 0.0117496, 916.596},
          {0.0674606, 0.0450853, 2592.11},
          {0.159563, 0.0405189, 3603.0},
          {0.196928, 0.035962, 4525.41}};
}

}  // namespace toolpoint::bench
