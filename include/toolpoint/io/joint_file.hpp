// toolpoint: an identified joint as a file — its constants, their covariance and how it was
// identified — that every command working from an assembly takes with one option
// (`--joint holder-tool=kht.toml`), so nobody copies eight numbers by hand.
//
// Format (TOML, SI units; written by `toolpoint identify --joint-output`):
//   [joint]
//   interface = "holder_tool"        # or "spindle_holder": which joint of an assembly it replaces
//   k_yf = 4.19e7                    # the eight parameters, as in an assembly file's [joints.*]
//   …                                # (k_tf, c_tf default to k_ym, c_ym)
//   [uncertainty]                    # optional
//   confidence = 0.95
//   lower = [ … ]  upper = [ … ]     # per parameter, order k_yf, c_yf, k_ym, c_ym, k_tf, c_tf, k_tm, c_tm
//   determined = [ … ]
//   covariance = [[ … ], …]          # 8×8, SI units, same order; symmetric positive semidefinite
//   [identification]                 # optional, free: how it was identified (strings and numbers)
// Units of the parameters and covariance entries: joint.hpp.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/identify/identified_joint.hpp"

namespace toolpoint {

// TOML text of the file (shortest round-trip numbers: reading it back gives the same doubles).
std::string format_joint_file(const JointFile& file);
// Written whole or not at all (AtomicOutput). Throws IoError naming the path.
void write_joint_file(const std::string& path, const JointFile& file);

// Reads a joint file. Throws InputError "file:line: …" for syntax errors, unknown or missing keys,
// non-finite values, a covariance that is not 8×8, not symmetric or not positive semidefinite;
// IoError when it cannot be read.
JointFile parse_joint_file(const std::string& text, const std::string& source);
JointFile load_joint_file(const std::string& path);

// with_joint (identified_joint.hpp) for an assembly read from its file; besides, what the file's notes said of the
// replaced joint (an indefinite stiffness or damping matrix, joint_warnings) gives way to what is
// true of the joint put in, named by the joint file.
LoadedAssembly with_joint(LoadedAssembly loaded, const JointFile& file);

}  // namespace toolpoint
