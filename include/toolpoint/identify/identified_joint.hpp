// toolpoint: an identified joint as a value — its constants, their covariance and how it was
// identified — as a joint file holds it (joint_file.hpp reads and writes the file; the Monte Carlo
// of uncertainty.hpp samples it). No file format here: the numerical headers depend on this one,
// the file format on it too, never the reverse.
// Units of the parameters and covariance entries: joint.hpp; parameter order k_yf, c_yf, k_ym, c_ym,
// k_tf, c_tf, k_tm, c_tm.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/model/joint.hpp"

namespace toolpoint {

enum class JointInterface { HolderTool, SpindleHolder };
const char* to_string(JointInterface i);  // "holder_tool", "spindle_holder"

struct JointUncertainty {
  double confidence = 0.95;
  std::array<double, 8> lower{}, upper{};
  std::array<bool, 8> determined{};
  Eigen::Matrix<double, 8, 8> covariance = Eigen::Matrix<double, 8, 8>::Zero();
};

// The content of a joint file (the name says where it usually comes from; nothing here reads one).
struct JointFile {
  JointInterface interface = JointInterface::HolderTool;
  JointParameters parameters;
  std::optional<JointUncertainty> uncertainty;
  // [identification]: key and value as written (strings, or numbers in shortest round-trip form).
  std::vector<std::pair<std::string, std::string>> identification;
  std::string source;  // the path it was read from (messages)
};

// What a joint file says against its own use: an [identification] verdict other than "pass" (an
// identification judged doubtful, or one judged fail and written all the same). One message each,
// naming the file.
std::vector<std::string> joint_file_warnings(const JointFile& file);

// The assembly with the file's joint in place of the one at its interface, carrying the file's
// warnings (Joint::warnings = joint_file_warnings), so every result computed with it repeats them.
Assembly with_joint(const Assembly& assembly, const JointFile& file);

}  // namespace toolpoint
