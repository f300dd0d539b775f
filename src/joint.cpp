// toolpoint: joint parameters and K(ω) (seed Eq. 8).
#include "toolpoint/joint.hpp"

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
    if (!std::isfinite((*this)[i])) throw InvalidArgument(fmt::format("joint parameter {} = {} is not finite", kNames[i], (*this)[i]));
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
