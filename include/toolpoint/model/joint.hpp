// toolpoint: elastic joints — the 8 contact parameters of seed Eq. (8) and the complex stiffness K(ω).
//
//   K(ω) = [[k_yf + iω c_yf,  k_ym + iω c_ym],
//           [k_θf + iω c_θf,  k_θm + iω c_θm]]
// Units: k_yf N/m, c_yf N·s/m; k_ym N·m/m = N, c_ym N·s; k_θf N/rad, c_θf N·s/rad;
// k_θm N·m/rad, c_θm N·m·s/rad. ω = 2πf in rad/s.
// K maps the relative displacement and rotation (w, θ) of the outer body's end 2 minus the inner
// body's end 1 to the force and moment (f, m) on the inner body (conventions.hpp). Reciprocity
// asks k_ym = k_θf and c_ym = c_θf; the seed keeps all eight to absorb measurement error.
// An indefinite K is legal (the seed's Table 1 has det ≈ −1.5e12).
#pragma once

#include <string>
#include <vector>

#include "toolpoint/model/receptance.hpp"

namespace toolpoint {

// The eight parameters by name, in the order of JointParameters' fields (θ spelt "t").
enum class JointParameter : int { k_yf, c_yf, k_ym, c_ym, k_tf, c_tf, k_tm, c_tm };

struct JointParameters {
  double k_yf = 0.0, c_yf = 0.0;  // N/m, N·s/m
  double k_ym = 0.0, c_ym = 0.0;  // N, N·s
  double k_tf = 0.0, c_tf = 0.0;  // N/rad, N·s/rad   (θf)
  double k_tm = 0.0, c_tm = 0.0;  // N·m/rad, N·m·s/rad (θm)

  // Eq. (8) at `frequency_hz`.
  Block stiffness(double frequency_hz) const;
  // Throws InvalidArgument naming the parameter if any value is not finite.
  void check() const;
  // Value i in the order k_yf, c_yf, k_ym, c_ym, k_θf, c_θf, k_θm, c_θm.
  double& operator[](int i);
  double operator[](int i) const;
  static const char* name(int i);  // "k_yf", …, with θ spelt "t": "k_tf"
  static const char* unit(int i);  // SI unit of value i
  double& operator[](JointParameter p) { return (*this)[static_cast<int>(p)]; }
  double operator[](JointParameter p) const { return (*this)[static_cast<int>(p)]; }
  static const char* name(JointParameter p) { return name(static_cast<int>(p)); }
  static const char* unit(JointParameter p) { return unit(static_cast<int>(p)); }
  // Value i is a damping (c: Im K / ω) when odd, a stiffness (k: Re K) when even; it belongs to
  // the entry (row(i), column(i)) of K.
  static bool is_damping(int i) { return i % 2 == 1; }
  static int row(int i) { return i / 4; }
  static int column(int i) { return (i / 2) % 2; }
  // The inverse: the index of the stiffness and of the damping of the entry (row, column) of K
  // ((0, 1) → k_ym, c_ym; (1, 0) → k_θf, c_θf).
  static int stiffness_of(int row, int column) { return 4 * row + 2 * column; }
  static int damping_of(int row, int column) { return stiffness_of(row, column) + 1; }
  // Value i's counterpart in the transposed entry of K, the value reciprocity makes equal to it
  // (k_ym ↔ k_θf, c_ym ↔ c_θf); a diagonal value is its own.
  static int transposed(int i) { return is_damping(i) ? damping_of(column(i), row(i)) : stiffness_of(column(i), row(i)); }
};

// A joint between two components: elastic with parameters, or rigid (K⁻¹ = 0).
struct Joint {
  bool rigid = true;
  JointParameters parameters;
  // What its source says against using it (a joint file whose identification was judged doubtful
  // or fail: joint_file_warnings in joint_file.hpp). Every result computed with an assembly that
  // holds the joint repeats them (Assembly::warnings, AssemblyModel::warnings).
  std::vector<std::string> warnings;

  static Joint make_rigid() { return {}; }
  static Joint make_elastic(const JointParameters& p) { return {false, p, {}}; }
};

// Warnings about a joint that is legal but worth knowing: an indefinite symmetric part of the
// stiffness (Re K) or damping (C) — the structure then has a motion of negative stiffness (it
// can diverge statically) or of negative damping (it feeds energy in). The seed's Table 1 has both:
// det(sym k) ≈ −1.5e12 (the tool rotating rigidly about a point 49 mm out, its tip in the seed's
// experiment) and det(sym c) = 54·1 − 22.2² < 0. `name` labels the messages.
std::vector<std::string> joint_warnings(const JointParameters& p, const std::string& name);

// The seed's analytical case study, Table 1 (holder–tool joint).
JointParameters seed_table1_joint();

// Parameters from a complex stiffness at one frequency: k = Re K, c = Im K / ω (seed Section 3).
JointParameters parameters_from_stiffness(const Block& K, double frequency_hz);

}  // namespace toolpoint
