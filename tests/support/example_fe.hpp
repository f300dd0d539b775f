// Test oracle: the example assembly (examples/bt40_shrinkfit_16mm.toml) rebuilt as a
// finite-element model (fe_beam.hpp: global matrices, direct solve; nothing of the library's
// coupling), its geometry typed in here from the example file. Materials and joints come from the
// loaded Assembly, so a test can vary them.
//   spindle: from the rear to the nose, cut at the bearings, which are springs to ground;
//   holder:  from the gauge line to its tip, the 16 mm carbide shank filling the bore over the
//            outer 74 mm (the flange's outer 4 mm and both outer segments);
//   tool:    outside the holder, 17 mm of 16 mm shank, then 32 mm fluted at 0.8 × 16 mm;
//   joints:  [[K, −K], [−K, K]] elements (spindle–holder at the gauge line, holder–tool at the
//            holder tip).
// Units: SI (m); element length in m.
#pragma once

#include <vector>

#include "support/fe_beam.hpp"
#include "toolpoint/model/assembly.hpp"

namespace toolpoint::test {

struct ExampleFe {
  fe_oracle::Chain spindle, holder, tool;  // tool: empty chain when built without the tool
  std::vector<int> tool_stations;          // nodes at ExampleFeOptions::tool_stations_m, in that order
  std::vector<int> holder_stations;        // nodes at ExampleFeOptions::holder_stations_m
};

struct ExampleFeOptions {
  double element_length = 0.002;          // m
  bool with_tool = true;                  // false: the spindle–holder subassembly (for SH11)
  std::vector<double> tool_stations_m;    // distances from the tool tip that get nodes, in [0, 0.049]
  std::vector<double> holder_stations_m;  // distances from the holder tip that get nodes, in [0, 0.086]
};

// Builds the model into `fem` (mesh not set: call fem.set_mesh).
ExampleFe build_example_fe(fe_oracle::FeModel& fem, const Assembly& example, const ExampleFeOptions& options = {});

}  // namespace toolpoint::test
