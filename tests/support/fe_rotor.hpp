// Test oracle: a finite-element rotor — a free–free uniform Timoshenko shaft spinning about its
// axis, in real coordinates. Used by tests/spin_test.cpp and tests/spin_assembly_test.cpp.
//
// Per node four DOFs (w_x, ψ_x, w_y, ψ_y) (x, y transverse, z the axis from node 0 to node n,
// right-handed; ψ = dw/dz in each plane, as beam.hpp's spinning segment), IIE Timoshenko elements
// (fe_beam.hpp: consistent mass, exact static stiffness) in each plane, and the gyroscopic matrix
// from the slice's angular momentum ρI_p Ω (ψ_x, ψ_y) + ρI (−ψ̇_y, ψ̇_x), ρI_p = 2ρI:
//     M q̈ + Ω G q̇ + K q = f,   G on (ψ_x, ψ_y) = +∫ρI_p N_ψᵀN_ψ, on (ψ_y, ψ_x) its negative.
// No complex coordinate, no whirl decoupling, no closed form. Units SI.
#pragma once

#include <Eigen/Dense>

#include "support/fe_beam.hpp"
#include "toolpoint/model/beam.hpp"

namespace fe_oracle {

struct FeRotor {
  Eigen::MatrixXcd K;  // complex for structural damping
  Eigen::MatrixXd M, G;
  int nodes = 0;
};

// `n` equal elements over `length`; DOF 4k + {0, 1, 2, 3} = (w_x, ψ_x, w_y, ψ_y) of node k.
inline FeRotor fe_rotor(const toolpoint::SectionProperties& p, double length, int n) {
  const double l = length / n;
  const ElementMatrices e = timoshenko_element(p.EI, p.kGA, p.rhoA, p.rhoI, l);
  // ∫ρI_p N_ψᵀ N_ψ: the rotary part of the consistent mass with ρI_p = 2ρI and no ρA.
  const Eigen::Matrix4d gp = timoshenko_element(p.EI, p.kGA, 0.0, 2.0 * p.rhoI, l).mass;
  FeRotor r;
  r.nodes = n + 1;
  const int N = 4 * r.nodes;
  r.K = Eigen::MatrixXcd::Zero(N, N);
  r.M = Eigen::MatrixXd::Zero(N, N);
  r.G = Eigen::MatrixXd::Zero(N, N);
  for (int k = 0; k < n; ++k) {
    // Element DOF i (w1, ψ1, w2, ψ2) → node k + i/2, DOF i%2 within a plane; y plane 2 further.
    auto x_of = [&](int i) { return 4 * (k + i / 2) + i % 2; };
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        const int xi = x_of(i), xj = x_of(j), yi = xi + 2, yj = xj + 2;
        r.K(xi, xj) += e.stiffness(i, j);
        r.K(yi, yj) += e.stiffness(i, j);
        r.M(xi, xj) += e.mass(i, j);
        r.M(yi, yj) += e.mass(i, j);
        r.G(xi, yj) += gp(i, j);  // moment on ψ_x: +ρI_p Ω ψ̇_y
        r.G(yi, xj) -= gp(i, j);  // moment on ψ_y: −ρI_p Ω ψ̇_x
      }
  }
  return r;
}

// The dynamic stiffness K + iωΩG − ω²M at ω [rad/s], spin Ω [rad/s].
inline Eigen::MatrixXcd dynamic_stiffness(const FeRotor& r, double omega, double spin) {
  return r.K + std::complex<double>(0.0, omega * spin) * r.G.cast<std::complex<double>>() -
         (omega * omega) * r.M.cast<std::complex<double>>();
}

}  // namespace fe_oracle
