// toolpoint: joint parameters and K(ω) (seed Eq. 8).
#include "toolpoint/model/joint.hpp"

#include <cmath>
#include <fmt/format.h>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

namespace {
constexpr const char* kNames[8] = {"k_yf", "c_yf", "k_ym", "c_ym", "k_tf", "c_tf", "k_tm", "c_tm"};
constexpr const char* kUnits[8] = {"N/m", "N s/m", "N", "N s", "N/rad", "N s/rad", "N m/rad", "N m s/rad"};
}  // namespace

Block JointParameters::stiffness(double frequency_hz) const {
  const double w = omega_of(frequency_hz);
  return make_block({k_yf, w * c_yf}, {k_ym, w * c_ym}, {k_tf, w * c_tf}, {k_tm, w * c_tm});
}

double& JointParameters::operator[](int i) {
  double* v[8] = {&k_yf, &c_yf, &k_ym, &c_ym, &k_tf, &c_tf, &k_tm, &c_tm};
  if (i < 0 || i > 7) throw InvalidArgument(fmt::format("joint parameter index {} outside 0..7", i));
  return *v[i];
}

double JointParameters::operator[](int i) const { return const_cast<JointParameters&>(*this)[i]; }

const char* JointParameters::name(int i) { return (i >= 0 && i < 8) ? kNames[i] : "?"; }
const char* JointParameters::unit(int i) { return (i >= 0 && i < 8) ? kUnits[i] : "?"; }

void JointParameters::check() const {
  for (int i = 0; i < 8; ++i)
    if (!std::isfinite((*this)[i]))
      throw InvalidArgument(fmt::format("joint parameter {} = {} is not finite", kNames[i], (*this)[i]));
}

std::vector<std::string> joint_warnings(const JointParameters& p, const std::string& name) {
  std::vector<std::string> w;
  // sym([[a, b], [c, d]]) is definite when a, d > 0 and a d > ((b + c)/2)².
  auto indefinite = [](double a, double b, double c, double d) {
    const double off = 0.5 * (b + c);
    return !(a > 0.0 && d > 0.0 && a * d > off * off);
  };
  const bool k_zero = p.k_yf == 0.0 && p.k_ym == 0.0 && p.k_tf == 0.0 && p.k_tm == 0.0;
  const bool c_zero = p.c_yf == 0.0 && p.c_ym == 0.0 && p.c_tf == 0.0 && p.c_tm == 0.0;
  if (!k_zero && indefinite(p.k_yf, p.k_ym, p.k_tf, p.k_tm)) {
    const double off = 0.5 * (p.k_ym + p.k_tf);
    w.push_back(
        fmt::format("{}: the stiffness matrix is not positive definite (k_yf k_tm − ((k_ym + k_tf)/2)² = {:.3g}): the "
                    "assembly has a motion of negative stiffness and is statically unstable; its FRFs are still "
                    "computed, as the seed's Table 1 joint requires",
                    name, p.k_yf * p.k_tm - off * off));
  }
  if (!c_zero && indefinite(p.c_yf, p.c_ym, p.c_tf, p.c_tm)) {
    const double off = 0.5 * (p.c_ym + p.c_tf);
    w.push_back(
        fmt::format("{}: the damping matrix is not positive definite (c_yf c_tm − ((c_ym + c_tf)/2)² = {:.3g}): some "
                    "motions gain energy from the joint",
                    name, p.c_yf * p.c_tm - off * off));
  }
  return w;
}

JointParameters seed_table1_joint() {
  JointParameters p;
  p.k_yf = 4.19e7;
  p.c_yf = 54.0;
  p.k_ym = 2.06e6;
  p.c_ym = 22.2;
  p.k_tf = 2.06e6;
  p.c_tf = 22.2;
  p.k_tm = 6.5e4;
  p.c_tm = 1.0;
  return p;
}

JointParameters parameters_from_stiffness(const Block& K, double frequency_hz) {
  const double w = omega_of(frequency_hz);
  JointParameters p;
  p.k_yf = K(0, 0).real();
  p.c_yf = K(0, 0).imag() / w;
  p.k_ym = K(0, 1).real();
  p.c_ym = K(0, 1).imag() / w;
  p.k_tf = K(1, 0).real();
  p.c_tf = K(1, 0).imag() / w;
  p.k_tm = K(1, 1).real();
  p.c_tm = K(1, 1).imag() / w;
  return p;
}

}  // namespace toolpoint
