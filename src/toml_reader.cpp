// toolpoint (internal): TOML reading shared by the file readers (toml_reader.hpp).
#include "toml_reader.hpp"

namespace toolpoint {

Joint read_joint_table(Reader& r, const toml::table* t, const std::string& path, bool joint_file) {
  if (!t) return Joint::make_rigid();
  if (joint_file) r.only(*t, path, {"interface", "k_yf", "c_yf", "k_ym", "c_ym", "k_tf", "c_tf", "k_tm", "c_tm"});
  else r.only(*t, path, {"rigid", "k_yf", "c_yf", "k_ym", "c_ym", "k_tf", "c_tf", "k_tm", "c_tm"});
  if (r.boolean(*t, "rigid", path).value_or(false)) {
    if (t->size() > 1) r.fail(*t, fmt::format("[{}] has rigid = true and stiffness values: choose one", path));
    return Joint::make_rigid();
  }
  JointParameters p;
  for (int i = 0; i < 8; ++i) {
    auto v = r.number(*t, JointParameters::name(i), path, JointParameters::unit(i));
    // θf terms default to the ym ones: a reciprocal joint needs only six values.
    if (!v && (i == 4 || i == 5)) v = r.number(*t, JointParameters::name(i - 2), path, JointParameters::unit(i - 2));
    if (!v)
      r.fail(*t, fmt::format("missing key {} (in {})", Reader::join(path, JointParameters::name(i)), JointParameters::unit(i)),
             "give k_yf, c_yf, k_ym, c_ym, k_tm, c_tm (and k_tf, c_tf if they differ from k_ym, c_ym), or rigid = true");
    p[i] = *v;
  }
  r.plausible(*t, "k_yf", path, p.k_yf, plausible::kJointTranslationalStiffness);
  r.plausible(*t, "k_tm", path, p.k_tm, plausible::kJointRotationalStiffness);
  r.plausible(*t, "c_yf", path, p.c_yf, plausible::kJointTranslationalDamping);
  r.plausible(*t, "c_tm", path, p.c_tm, plausible::kJointRotationalDamping);
  return Joint::make_elastic(p);
}

}  // namespace toolpoint
