// toolpoint: an identified joint as a value (identified_joint.hpp).
#include "toolpoint/identify/identified_joint.hpp"

#include <fmt/format.h>

namespace toolpoint {

const char* to_string(JointInterface i) { return i == JointInterface::HolderTool ? "holder_tool" : "spindle_holder"; }

std::vector<std::string> joint_file_warnings(const JointFile& file) {
  std::vector<std::string> w;
  for (const auto& [key, value] : file.identification) {
    if (key != "verdict" || value == "pass") continue;
    w.push_back(
        fmt::format("{}: the identification of this {} joint was judged '{}' ([identification] verdict){}: every "
                    "result computed with it carries that doubt",
                    file.source.empty() ? "joint file" : file.source, to_string(file.interface), value,
                    value == "fail" ? ", and the file was written all the same" : ""));
  }
  return w;
}

Assembly with_joint(const Assembly& assembly, const JointFile& file) {
  Assembly a = assembly;
  Joint j = Joint::make_elastic(file.parameters);
  j.warnings = joint_file_warnings(file);
  (file.interface == JointInterface::HolderTool ? a.holder_tool : a.spindle_holder) = std::move(j);
  return a;
}

}  // namespace toolpoint
