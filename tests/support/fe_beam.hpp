// Test oracle: a planar Timoshenko beam finite-element model, solved directly per frequency.
//
// Why it exists: the library builds tool point FRFs by receptance coupling of exact free–free
// Timoshenko segments. Tests need an answer from a different method: this model assembles global
// stiffness, damping and mass matrices and solves (K + iΩC − Ω²M) x = F with a sparse LU at each
// frequency. It uses Eigen only — no library algorithm — so agreement is evidence, not an echo.
//
// Units (SI): lengths m, forces N, moments N·m, EI N·m², κGA N, ρA kg/m, ρI kg·m, translational
// springs N/m, rotational springs N·m/rad, dampers N·s/m and N·m·s/rad; frequencies in Hz at every
// interface (Ω = 2πf in rad/s inside).
//
// Sign convention (the project's, conventions.hpp): one axis x, increasing along every chain;
// per node two DOFs (w, ψ): w transverse displacement [m], ψ the bending rotation of the cross
// section [rad], positive like dw/dx along +x; f force along w, m moment in the sense of ψ.
// A receptance block is [[w_r/f_l, w_r/m_l], [ψ_r/f_l, ψ_r/m_l]] (toolpoint::Block layout).
//
// Element: two nodes, the exact-static-shape ("interdependent interpolation", IIE) Timoshenko
// element of Friedman & Kosmatka (Comput. Struct. 47 (1993) 473), shear parameter
// Φ = 12 EI/(κGA l²). Its stiffness is the exact static stiffness of a uniform Timoshenko beam,
// so any static problem is solved exactly with one element per segment. Mass is consistent
// (translational ρA and rotary ρI) with the same static shapes.
// Convergence (observed, tests/fe_oracle_test.cpp): frequencies and receptances converge like h²
// for thick beams (the shear strain is constant per element, so its energy-norm error is O(h)),
// like h⁴ only where shear energy is negligible (slender beams). Hence the Richardson option:
// R ≈ (4 R(h/2) − R(h))/3 removes the h² term; for a hollow L/D = 3 segment up to 30 kHz it
// brings the worst entry from 3e-4 (128 elements) to 2e-5 (64 and 128 elements).
// Damping: structural damping enters as complex EI and κGA. The static stiffness is a rational,
// hence analytic, function of (EI, κGA), so it is evaluated as is in complex arithmetic (complex
// Φ when EI and κGA carry different loss factors: the element then remains statically exact for
// the complex moduli, by the correspondence principle). The mass matrix only needs shapes that
// converge, so it uses the real shapes, Φ_m = 12 Re(EI)/(Re(κGA) l²); with one loss factor for
// both moduli Φ is real and the two coincide.
//
// How to use it (e.g. to check a coupled spindle–holder–tool assembly):
//   1. Describe each body as a chain of uniform segments listed in order of increasing x, i.e.
//      from the spindle rear towards the tool tip. NOTE: toolpoint::Segment lists go the other
//      way (end 1, the outer end, first); reverse them. A section is (EI, κGA, ρA, ρI), e.g. from
//      toolpoint::Segment::properties(). FeSegment::elements sets the base mesh.
//   2. FeModel::add_chain(segments, x_start) returns the chain's nodes: the segment boundaries,
//      by increasing x (nodes[0] the chain start, nodes[k] the end of segment k−1). Only these
//      are addressable; interior mesh nodes are internal. Put a segment boundary wherever a
//      bearing, joint, load or response point is needed.
//   3. Bearings: add_ground_spring(node, k_w, k_ψ, c_w, c_ψ) adds k + iΩc to ground on the
//      node's DOFs (complex k for structural damping). Joints between bodies (spindle–holder,
//      holder–tool): add_joint(a, b, K, C) with the element matrix [[Z, −Z], [−Z, Z]] on the DOFs
//      of (a, b), Z = K + iΩC, so the force on b is Z (x_a − x_b) and on a its opposite; with
//      a = outer body's end 2 and b = inner body's end 1 this is the project's joint convention.
//      K may be non-symmetric or indefinite (only natural_frequencies_hz() needs Re Z symmetric).
//      A perfectly rigid connection: add_rigid_link(a, b) merges the two nodes' DOFs.
//      Clamps: fix(node, w, ψ) removes DOFs exactly (their receptances are then 0).
//   4. set_mesh({refinement, richardson}): every segment gets elements × refinement elements;
//      with richardson, results combine refinement r and 2r (3× the work, far more accurate).
//      Sizing: for steel up to 30 kHz, elements of ~2.3 mm (64 over 150 mm) gave ≤ 1.2e-3
//      raw and ≤ 2e-5 with Richardson (errors relative to each entry's peak over the band).
//      To know the error of your own model, compare refinement r with 2r.
//   5. receptance(f, response, load) gives one 2×2 block; receptance_all(f, nodes) all blocks
//      among `nodes` from one factorisation; receptance_series over a grid. A tool point FRF is
//      receptance(f, tip, tip); a free–free segment's T11, T12, T21, T22 (end 1 at x = L) are
//      receptance(f, last, last), (last, first), (first, last), (first, first).
//   6. Keep models small (a few hundred DOFs): each frequency is one sparse LU factorisation
//      (300 DOFs: ~0.3 ms). Assembled matrices are cached per refinement and dropped by any
//      add_*/fix call, so a const FeModel is not safe to use from several threads at once.
// Accuracy limit at low frequency: a free body's receptance near 0 Hz is ill-conditioned
// (round-off error ≈ 2e-15 × the scaled condition number, which grows like 1/f²: a free
// 64-element 100 mm stub is good to ~2e-5 at 1 Hz). Compare free bodies from ~10 Hz up.
// Errors: bad arguments throw std::invalid_argument naming the value. A singular or numerically
// singular dynamic stiffness (scaled condition estimate > 1e11, i.e. round-off possibly above
// ~2e-4: a free body at or very near 0 Hz, an undamped resonance hit almost exactly) throws
// std::runtime_error naming the frequency.
#pragma once

#include <Eigen/Core>
#include <array>
#include <complex>
#include <map>
#include <memory>
#include <vector>

#include "toolpoint/model/receptance.hpp"

namespace fe_oracle {

using Complex = std::complex<double>;

// A uniform length of beam and how finely to mesh it.
struct FeSegment {
  double length = 0.0;  // m, > 0
  Complex EI;           // bending stiffness [N·m²], Re > 0 (Im = η Re for structural damping)
  Complex kGA;          // shear stiffness κGA [N], Re > 0
  double rhoA = 0.0;    // mass per length [kg/m], > 0
  double rhoI = 0.0;    // rotary inertia per length [kg·m], ≥ 0
  int elements = 1;     // equal elements over the length, ≥ 1

  void check() const;  // throws std::invalid_argument naming the value
};

// One IIE element of length l on DOFs (w1, ψ1, w2, ψ2), node 1 at the smaller x.
//   stiffness = EI/((1+Φ) l³) [[12, 6l, −12, 6l], [6l, (4+Φ)l², −6l, (2−Φ)l²],
//                              [−12, −6l, 12, −6l], [6l, (2−Φ)l², −6l, (4+Φ)l²]] (F&K 1993)
//   mass = ∫₀ˡ (ρA N_wᵀ N_w + ρI N_ψᵀ N_ψ) dx with the static shapes
//     w = Σ aᵢ ξⁱ (cubic, ξ = x/l),  ψ = (a₁ + 2a₂ξ + 3a₃ξ² + (Φ/2) a₃)/l,
//   integrated exactly by 4-point Gauss–Legendre (integrands of degree ≤ 6); it equals F&K's
//   closed-form consistent mass (checked in the tests).
struct ElementMatrices {
  Eigen::Matrix4cd stiffness;
  Eigen::Matrix4d mass;
};
ElementMatrices timoshenko_element(Complex EI, Complex kGA, double rhoA, double rhoI, double l);

// The addressable nodes of one chain: its segment boundaries by increasing x.
struct Chain {
  std::vector<int> nodes;  // size = segments + 1
  int first() const { return nodes.front(); }
  int last() const { return nodes.back(); }
};

// How finely to mesh, and whether to extrapolate.
struct MeshOptions {
  int refinement = 1;       // elements per segment = FeSegment::elements × refinement, ≥ 1
  bool richardson = false;  // R = (4 R(2·refinement) − R(refinement))/3, removing the h² error
  void check() const;
};

class FeModel {
 public:
  FeModel();
  ~FeModel();
  FeModel(const FeModel&) = delete;
  FeModel& operator=(const FeModel&) = delete;

  // Adds a new, unconnected chain of segments starting at x = x_start [m].
  Chain add_chain(const std::vector<FeSegment>& segments, double x_start = 0.0);

  // k + iΩc to ground on the node's w and ψ: k_w [N/m], k_psi [N·m/rad] (complex for structural
  // damping), c_w [N·s/m], c_psi [N·m·s/rad]. Springs at one node add up.
  void add_ground_spring(int node, Complex k_w, Complex k_psi, double c_w = 0.0, double c_psi = 0.0);

  // Joint Z = K + iΩC between nodes a and b: force on b = Z (x_a − x_b), x = (w, ψ).
  // K [[N/m, N/rad], [N·m/m, N·m/rad]], C the same per (rad/s).
  void add_joint(int node_a, int node_b, const Eigen::Matrix2cd& K, const Eigen::Matrix2d& C = Eigen::Matrix2d::Zero());

  // Rigid connection: nodes a and b share both DOFs (w and ψ equal).
  void add_rigid_link(int node_a, int node_b);

  // Clamps the node's w and/or ψ (exact elimination; also applies to nodes rigidly linked to it).
  void fix(int node, bool w = true, bool psi = true);

  void set_mesh(const MeshOptions& mesh);
  const MeshOptions& mesh() const { return mesh_; }

  int node_count() const { return static_cast<int>(x_.size()); }
  double x(int node) const;  // node position [m]
  int dof_count() const;     // free DOFs of the mesh at mesh().refinement, after links and clamps

  // One receptance block [[w_r/f_l, w_r/m_l], [ψ_r/f_l, ψ_r/m_l]] at f_hz ≥ 0.
  toolpoint::Block receptance(double f_hz, int response_node, int load_node) const;
  // All blocks among `nodes` from one factorisation: a 2n × 2n matrix ordered
  // (w_0, ψ_0, w_1, ψ_1, …) over `nodes`; block (i, j) = receptance(f, nodes[i], nodes[j]).
  Eigen::MatrixXcd receptance_all(double f_hz, const std::vector<int>& nodes) const;
  // receptance() over a frequency grid [Hz].
  toolpoint::BlockSeries receptance_series(const std::vector<double>& frequencies_hz, int response_node, int load_node) const;

  // Natural frequencies [Hz] of the undamped model (Re EI, Re κGA, Re of springs and joints, no
  // dampers) at mesh().refinement (no extrapolation), ascending, one per free DOF; rigid-body
  // modes give ~0 (negative round-off eigenvalues are reported as 0). Throws
  // std::invalid_argument if a joint's Re K is not symmetric, std::runtime_error if the mass
  // matrix is not positive definite.
  std::vector<double> natural_frequencies_hz() const;

 private:
  struct Spring {
    int a, b;  // b = −1: to ground
    Eigen::Matrix2cd K;
    Eigen::Matrix2d C;
  };
  struct ChainData {
    std::vector<FeSegment> segments;
    std::vector<int> nodes;
  };
  struct Assembly;

  void require_node(int node, const char* what) const;
  void invalidate();
  const Assembly& assembly(int refinement) const;
  Eigen::MatrixXcd solve(double f_hz, const std::vector<int>& response_nodes, const std::vector<int>& load_nodes,
                         int refinement) const;
  Eigen::MatrixXcd solve(double f_hz, const std::vector<int>& response_nodes, const std::vector<int>& load_nodes) const;

  std::vector<double> x_;
  std::vector<ChainData> chains_;
  std::vector<Spring> springs_;
  std::vector<std::pair<int, int>> links_;
  std::vector<std::array<bool, 2>> fixed_;  // per node: w, ψ clamped
  MeshOptions mesh_;
  mutable std::map<int, std::unique_ptr<Assembly>> assemblies_;  // by refinement
};

}  // namespace fe_oracle
