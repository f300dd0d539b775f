// toolpoint: the assembly file (TOML). Every key is documented in examples/bt40_shrinkfit_16mm.toml.
//
// Units: SI throughout — lengths and diameters in m, moduli in Pa, density in kg/m³, bearing and
// joint stiffness in N/m, N, N/rad, N·m/rad, damping in N·s/m, N·s, N·s/rad, N·m·s/rad,
// frequencies in Hz. Positions on the spindle are metres from the spindle nose, inwards.
// Segments are listed from each component's outer end inwards (spindle: nose → rear; holder:
// tip → taper end). Unknown or misspelt keys are errors (with a suggestion); values that look
// like millimetres or MPa give warnings naming the key.
#pragma once

#include <string>
#include <vector>

#include "toolpoint/model/assembly.hpp"

namespace toolpoint {

struct LoadedAssembly {
  Assembly assembly;
  std::vector<std::string> warnings;  // "file:line: key = value …" for implausible magnitudes
  // Legal but worth knowing: the default grid; an indefinite joint (joint_warnings, each named
  // assembly_joint_name(source, key)).
  std::vector<std::string> notes;
  std::string source;  // the file (or name) it was read from
};

// How an assembly file's messages name one of its joints: "<source>: joints.<key>", key
// "holder_tool" or "spindle_holder".
std::string assembly_joint_name(const std::string& source, const std::string& key);

// Parses assembly TOML text; `source` names the file in errors ("file:line: key: what was
// expected"). Throws InputError for syntax errors, missing or unknown keys, wrong types and
// invalid values (the library's InvalidArgument re-thrown with the file and line).
LoadedAssembly parse_assembly(const std::string& text, const std::string& source);
LoadedAssembly load_assembly(const std::string& path);

}  // namespace toolpoint
