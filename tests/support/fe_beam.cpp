// Test oracle: planar Timoshenko beam FE model (see fe_beam.hpp). SI units, frequencies in Hz.
// Independent of the library's algorithms: global matrices, Eigen's sparse LU and generalised
// symmetric eigensolver only.
#include "support/fe_beam.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

namespace fe_oracle {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

void require(bool ok, const std::string& message) {
  if (!ok) throw std::invalid_argument(message);
}

bool finite(Complex z) { return std::isfinite(z.real()) && std::isfinite(z.imag()); }

}  // namespace

void FeSegment::check() const {
  require(std::isfinite(length) && length > 0.0, fmt::format("FeSegment: length = {} m must be > 0", length));
  require(finite(EI) && EI.real() > 0.0, fmt::format("FeSegment: EI = ({}, {}) N·m² needs Re > 0", EI.real(), EI.imag()));
  require(finite(kGA) && kGA.real() > 0.0, fmt::format("FeSegment: κGA = ({}, {}) N needs Re > 0", kGA.real(), kGA.imag()));
  require(std::isfinite(rhoA) && rhoA > 0.0, fmt::format("FeSegment: ρA = {} kg/m must be > 0", rhoA));
  require(std::isfinite(rhoI) && rhoI >= 0.0, fmt::format("FeSegment: ρI = {} kg·m must be ≥ 0", rhoI));
  require(elements >= 1, fmt::format("FeSegment: elements = {} must be ≥ 1", elements));
}

ElementMatrices timoshenko_element(Complex EI, Complex kGA, double rhoA, double rhoI, double l) {
  ElementMatrices e;
  // Exact static stiffness (Friedman & Kosmatka 1993), analytic in (EI, κGA).
  const Complex phi = 12.0 * EI / (kGA * l * l);
  const Complex s = EI / ((1.0 + phi) * l * l * l);
  const double l2 = l * l;
  e.stiffness << 12.0, 6.0 * l, -12.0, 6.0 * l,               //
      6.0 * l, (4.0 + phi) * l2, -6.0 * l, (2.0 - phi) * l2,  //
      -12.0, -6.0 * l, 12.0, -6.0 * l,                        //
      6.0 * l, (2.0 - phi) * l2, -6.0 * l, (4.0 + phi) * l2;
  e.stiffness *= s;

  // Consistent mass from the real static shapes. Nodal values d = T a of the shape coefficients
  // a (w = Σ aᵢ ξⁱ, ψ = (a₁ + 2a₂ξ + 3a₃ξ² + (Φ/2)a₃)/l, which solve the static Timoshenko
  // equations: κGA(w′ − ψ) = −6EI a₃/l³ is constant and balances EIψ″).
  const double phi_m = 12.0 * EI.real() / (kGA.real() * l2);
  Eigen::Matrix4d T;
  T << 1.0, 0.0, 0.0, 0.0,                 //
      0.0, 1.0 / l, 0.0, 0.5 * phi_m / l,  //
      1.0, 1.0, 1.0, 1.0,                  //
      0.0, 1.0 / l, 2.0 / l, (3.0 + 0.5 * phi_m) / l;
  const Eigen::Matrix4d Tinv = T.inverse();
  // 4-point Gauss–Legendre on [0, 1]: exact for the degree-6 products of cubic shapes.
  const double gx[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
  const double gw[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
  e.mass.setZero();
  for (int q = 0; q < 4; ++q) {
    const double xi = 0.5 * (1.0 + gx[q]), wq = 0.5 * gw[q] * l;
    const Eigen::RowVector4d nw = Eigen::RowVector4d(1.0, xi, xi * xi, xi * xi * xi) * Tinv;
    const Eigen::RowVector4d np = Eigen::RowVector4d(0.0, 1.0, 2.0 * xi, 3.0 * xi * xi + 0.5 * phi_m) / l * Tinv;
    e.mass += wq * (rhoA * nw.transpose() * nw + rhoI * np.transpose() * np);
  }
  return e;
}

// ---- Model description ---------------------------------------------------------------------------

void MeshOptions::check() const { require(refinement >= 1, fmt::format("MeshOptions: refinement = {} must be ≥ 1", refinement)); }

// Everything derived from the model description at one refinement, rebuilt after any change.
struct FeModel::Assembly {
  std::vector<std::array<int, 2>> dof;  // per public node: global DOF of w and ψ, −1 if clamped
  int n = 0;
  // K (complex), C, M share one sparsity pattern, so a frequency's matrix is a loop over values.
  Eigen::SparseMatrix<Complex> pattern;
  std::vector<Complex> k;
  std::vector<double> c, m;
  Eigen::SparseLU<Eigen::SparseMatrix<Complex>, Eigen::COLAMDOrdering<int>> lu;
  Eigen::MatrixXd k_undamped, m_dense;  // for the eigenproblem
};

FeModel::FeModel() = default;
FeModel::~FeModel() = default;

void FeModel::require_node(int node, const char* what) const {
  require(node >= 0 && node < node_count(),
          fmt::format("FeModel: {} node {} does not exist (model has {} nodes)", what, node, node_count()));
}

void FeModel::invalidate() { assemblies_.clear(); }

Chain FeModel::add_chain(const std::vector<FeSegment>& segments, double x_start) {
  require(!segments.empty(), "FeModel::add_chain: no segments");
  require(std::isfinite(x_start), fmt::format("FeModel::add_chain: x_start = {} m is not finite", x_start));
  for (const FeSegment& s : segments) s.check();
  invalidate();
  ChainData chain{segments, {}};
  double x = x_start;
  for (std::size_t k = 0; k <= segments.size(); ++k) {
    if (k > 0) x += segments[k - 1].length;
    x_.push_back(x);
    fixed_.push_back({false, false});
    chain.nodes.push_back(node_count() - 1);
  }
  chains_.push_back(chain);
  return Chain{chain.nodes};
}

void FeModel::add_ground_spring(int node, Complex k_w, Complex k_psi, double c_w, double c_psi) {
  require_node(node, "add_ground_spring:");
  require(finite(k_w) && finite(k_psi) && std::isfinite(c_w) && std::isfinite(c_psi),
          fmt::format("FeModel::add_ground_spring: non-finite value at node {}", node));
  invalidate();
  Eigen::Matrix2cd K = Eigen::Matrix2cd::Zero();
  K(0, 0) = k_w;
  K(1, 1) = k_psi;
  springs_.push_back({node, -1, K, Eigen::Vector2d(c_w, c_psi).asDiagonal()});
}

void FeModel::add_joint(int node_a, int node_b, const Eigen::Matrix2cd& K, const Eigen::Matrix2d& C) {
  require_node(node_a, "add_joint: a");
  require_node(node_b, "add_joint: b");
  require(node_a != node_b, fmt::format("FeModel::add_joint: a joint needs two different nodes (got {} twice)", node_a));
  require(K.allFinite() && C.allFinite(), "FeModel::add_joint: non-finite K or C");
  invalidate();
  springs_.push_back({node_a, node_b, K, C});
}

void FeModel::add_rigid_link(int node_a, int node_b) {
  require_node(node_a, "add_rigid_link: a");
  require_node(node_b, "add_rigid_link: b");
  invalidate();
  links_.emplace_back(node_a, node_b);
}

void FeModel::fix(int node, bool w, bool psi) {
  require_node(node, "fix:");
  invalidate();
  fixed_[node][0] = fixed_[node][0] || w;
  fixed_[node][1] = fixed_[node][1] || psi;
}

void FeModel::set_mesh(const MeshOptions& mesh) {
  mesh.check();
  mesh_ = mesh;
}

double FeModel::x(int node) const {
  require_node(node, "x:");
  return x_[node];
}

int FeModel::dof_count() const { return assembly(mesh_.refinement).n; }

// ---- Assembly ------------------------------------------------------------------------------------

const FeModel::Assembly& FeModel::assembly(int refinement) const {
  if (auto it = assemblies_.find(refinement); it != assemblies_.end()) return *it->second;
  require(!chains_.empty(), "FeModel: no chains (add one first)");
  auto a = std::make_unique<Assembly>();

  // Rigid links: union–find over the public nodes, each group's root carries the DOFs; a clamp
  // anywhere in a group clamps the group. Interior mesh nodes get DOFs of their own afterwards.
  std::vector<int> root(node_count());
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](int i) {
    while (root[i] != i) i = root[i] = root[root[i]];
    return i;
  };
  for (auto [p, q] : links_) root[find(p)] = find(q);
  std::vector<std::array<bool, 2>> group_fixed(node_count(), {false, false});
  for (int i = 0; i < node_count(); ++i)
    for (int d = 0; d < 2; ++d) group_fixed[find(i)][d] = group_fixed[find(i)][d] || fixed_[i][d];
  std::vector<std::array<int, 2>> root_dof(node_count(), {-1, -1});
  for (int i = 0; i < node_count(); ++i)
    if (find(i) == i)
      for (int d = 0; d < 2; ++d)
        if (!group_fixed[i][d]) root_dof[i][d] = a->n++;
  a->dof.resize(node_count());
  for (int i = 0; i < node_count(); ++i) a->dof[i] = root_dof[find(i)];

  // Coordinate list shared by K, C and M (explicit zeros keep the three patterns identical).
  struct Entry {
    int r, c;
    Complex k;
    double cv, m, k_undamped;
  };
  std::vector<Entry> entries;
  auto scatter = [&](const std::array<int, 4>& dofs, int size, auto&& value) {
    for (int i = 0; i < size; ++i)
      for (int j = 0; j < size; ++j)
        if (dofs[i] >= 0 && dofs[j] >= 0) {
          Entry e = value(i, j);
          e.r = dofs[i];
          e.c = dofs[j];
          entries.push_back(e);
        }
  };
  for (const ChainData& chain : chains_)
    for (std::size_t s = 0; s < chain.segments.size(); ++s) {
      const FeSegment& seg = chain.segments[s];
      const int count = seg.elements * refinement;
      const double l = seg.length / count;
      const ElementMatrices em = timoshenko_element(seg.EI, seg.kGA, seg.rhoA, seg.rhoI, l);
      const Eigen::Matrix4cd k0 = timoshenko_element(seg.EI.real(), seg.kGA.real(), seg.rhoA, seg.rhoI, l).stiffness;
      std::array<int, 2> left = a->dof[chain.nodes[s]];
      for (int e = 0; e < count; ++e) {
        const std::array<int, 2> right = e + 1 == count ? a->dof[chain.nodes[s + 1]] : std::array<int, 2>{a->n, a->n + 1};
        if (e + 1 < count) a->n += 2;
        scatter({left[0], left[1], right[0], right[1]}, 4,
                [&](int i, int j) { return Entry{0, 0, em.stiffness(i, j), 0.0, em.mass(i, j), k0(i, j).real()}; });
        left = right;
      }
    }
  if (a->n == 0) throw std::invalid_argument("FeModel: every DOF is clamped");
  for (const Spring& s : springs_) {
    // Ground: Z on the node. Joint: [[Z, −Z], [−Z, Z]] on (a, b).
    const std::array<int, 4> dofs = {a->dof[s.a][0], a->dof[s.a][1], s.b >= 0 ? a->dof[s.b][0] : -1,
                                     s.b >= 0 ? a->dof[s.b][1] : -1};
    scatter(dofs, s.b >= 0 ? 4 : 2, [&](int i, int j) {
      const double sign = (i / 2 == j / 2) ? 1.0 : -1.0;
      const Complex kk = sign * s.K(i % 2, j % 2);
      return Entry{0, 0, kk, sign * s.C(i % 2, j % 2), 0.0, kk.real()};
    });
  }

  std::vector<Eigen::Triplet<Complex>> tk, tc, tm;
  a->k_undamped = Eigen::MatrixXd::Zero(a->n, a->n);
  a->m_dense = Eigen::MatrixXd::Zero(a->n, a->n);
  for (const Entry& e : entries) {
    tk.emplace_back(e.r, e.c, e.k);
    tc.emplace_back(e.r, e.c, Complex(e.cv));
    tm.emplace_back(e.r, e.c, Complex(e.m));
    a->k_undamped(e.r, e.c) += e.k_undamped;
    a->m_dense(e.r, e.c) += e.m;
  }
  Eigen::SparseMatrix<Complex> K(a->n, a->n), C(a->n, a->n), M(a->n, a->n);
  K.setFromTriplets(tk.begin(), tk.end());
  C.setFromTriplets(tc.begin(), tc.end());
  M.setFromTriplets(tm.begin(), tm.end());
  K.makeCompressed();
  C.makeCompressed();
  M.makeCompressed();
  const auto nnz = static_cast<std::size_t>(K.nonZeros());
  if (C.nonZeros() != K.nonZeros() || M.nonZeros() != K.nonZeros() ||
      !std::equal(K.innerIndexPtr(), K.innerIndexPtr() + nnz, M.innerIndexPtr()) ||
      !std::equal(K.innerIndexPtr(), K.innerIndexPtr() + nnz, C.innerIndexPtr()))
    throw std::logic_error("FeModel: K, C and M patterns differ");
  a->pattern = K;
  a->k.assign(K.valuePtr(), K.valuePtr() + nnz);
  a->c.resize(nnz);
  a->m.resize(nnz);
  for (std::size_t i = 0; i < nnz; ++i) {
    a->c[i] = C.valuePtr()[i].real();
    a->m[i] = M.valuePtr()[i].real();
  }
  a->lu.analyzePattern(a->pattern);
  return *(assemblies_[refinement] = std::move(a));
}

// ---- Solutions ---------------------------------------------------------------------------------

namespace {

// Lower bound on cond(D⁻¹AD⁻¹) from the solved columns x (unit loads rhs); see solve().
double condition_estimate(const Eigen::SparseMatrix<Complex>& A, const std::vector<Complex>& k, const std::vector<double>& c,
                          const std::vector<double>& m, double w, const Eigen::MatrixXcd& x, const Eigen::MatrixXcd& rhs) {
  const Complex* v0 = A.valuePtr();
  Eigen::VectorXd d = Eigen::VectorXd::Zero(A.rows());
  for (Eigen::Index j = 0; j < A.outerSize(); ++j)
    for (Eigen::SparseMatrix<Complex>::InnerIterator it(A, j); it; ++it)
      if (it.row() == it.col()) {
        const auto i = &it.value() - v0;
        d(it.row()) = std::sqrt(std::abs(k[i]) + w * w * m[i] + w * std::abs(c[i]));
      }
  if (!(d.minCoeff() > 0.0)) return std::numeric_limits<double>::infinity();
  double a_max = 0.0;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j)
    for (Eigen::SparseMatrix<Complex>::InnerIterator it(A, j); it; ++it)
      a_max = std::max(a_max, std::abs(it.value()) / (d(it.row()) * d(it.col())));
  double inv = 0.0;
  for (Eigen::Index j = 0; j < rhs.cols(); ++j) {
    Eigen::Index g = 0;
    if (rhs.col(j).cwiseAbs().maxCoeff(&g) == 0.0) continue;  // load on a clamped DOF
    inv = std::max(inv, (x.col(j).cwiseAbs().cwiseProduct(d)).maxCoeff() * d(g));
  }
  return a_max * inv;
}

}  // namespace

Eigen::MatrixXcd FeModel::solve(double f_hz, const std::vector<int>& response_nodes, const std::vector<int>& load_nodes,
                                int refinement) const {
  Assembly& a = const_cast<Assembly&>(assembly(refinement));  // the LU workspace is a cache
  const double w = kTwoPi * f_hz;
  Complex* v = a.pattern.valuePtr();
  for (std::size_t i = 0; i < a.k.size(); ++i) v[i] = a.k[i] + Complex(-w * w * a.m[i], w * a.c[i]);
  a.lu.factorize(a.pattern);
  if (a.lu.info() != Eigen::Success)
    throw std::runtime_error(fmt::format("FeModel: dynamic stiffness is singular at {} Hz ({})", f_hz, a.lu.lastErrorMessage()));

  const auto nl = static_cast<Eigen::Index>(load_nodes.size());
  Eigen::MatrixXcd rhs = Eigen::MatrixXcd::Zero(a.n, 2 * nl);
  for (Eigen::Index j = 0; j < nl; ++j)
    for (int d = 0; d < 2; ++d)
      if (const int g = a.dof[load_nodes[j]][d]; g >= 0) rhs(g, 2 * j + d) = 1.0;
  const Eigen::MatrixXcd x = a.lu.solve(rhs);
  if (!x.allFinite()) throw std::runtime_error(fmt::format("FeModel: non-finite receptance at {} Hz", f_hz));
  // A factorisation "succeeds" on a numerically singular matrix (a free body at 0 Hz gives
  // finite garbage), so estimate the condition number of the diagonally scaled matrix
  // Â = D⁻¹AD⁻¹, d_i² = |K_ii| + Ω²M_ii + Ω|C_ii| (scaling makes w and ψ rows, and stiff
  // springs, comparable): cond(Â) ≥ max|Â_ij| · |D x_j|_∞ d_g for a unit load on DOF g.
  // Observed: a free 64-element stub gives 5e15 at 0 Hz and 7e9 at 1 Hz, where its error
  // against the rigid-body closed form is 1.5e-5, i.e. ≈ 2e-15 × the estimate (round-off: the
  // backward error ε‖Â‖ competes with the smallest eigenvalue). Refusing above 1e11 keeps that
  // error below ~2e-4.
  const double cond = condition_estimate(a.pattern, a.k, a.c, a.m, w, x, rhs);
  if (cond > 1e11)
    throw std::runtime_error(
        fmt::format("FeModel: dynamic stiffness is numerically singular at {} Hz (scaled "
                    "condition number ≥ {:.2g}); is a body free at 0 Hz?",
                    f_hz, cond));

  const auto nr = static_cast<Eigen::Index>(response_nodes.size());
  Eigen::MatrixXcd out = Eigen::MatrixXcd::Zero(2 * nr, 2 * nl);
  for (Eigen::Index i = 0; i < nr; ++i)
    for (int d = 0; d < 2; ++d)
      if (const int g = a.dof[response_nodes[i]][d]; g >= 0) out.row(2 * i + d) = x.row(g);
  return out;
}

Eigen::MatrixXcd FeModel::solve(double f_hz, const std::vector<int>& response_nodes, const std::vector<int>& load_nodes) const {
  require(std::isfinite(f_hz) && f_hz >= 0.0, fmt::format("FeModel: frequency {} Hz must be ≥ 0", f_hz));
  for (int r : response_nodes) require_node(r, "receptance: response");
  for (int l : load_nodes) require_node(l, "receptance: load");
  const int r = mesh_.refinement;
  if (!mesh_.richardson) return solve(f_hz, response_nodes, load_nodes, r);
  return (4.0 * solve(f_hz, response_nodes, load_nodes, 2 * r) - solve(f_hz, response_nodes, load_nodes, r)) / 3.0;
}

toolpoint::Block FeModel::receptance(double f_hz, int response_node, int load_node) const {
  return solve(f_hz, {response_node}, {load_node});
}

Eigen::MatrixXcd FeModel::receptance_all(double f_hz, const std::vector<int>& nodes) const { return solve(f_hz, nodes, nodes); }

toolpoint::BlockSeries FeModel::receptance_series(const std::vector<double>& frequencies_hz, int response_node,
                                                  int load_node) const {
  toolpoint::BlockSeries s;
  s.frequency_hz = frequencies_hz;
  s.blocks.reserve(frequencies_hz.size());
  for (double f : frequencies_hz) s.blocks.push_back(receptance(f, response_node, load_node));
  return s;
}

std::vector<double> FeModel::natural_frequencies_hz() const {
  const Assembly& a = assembly(mesh_.refinement);
  const double asym = (a.k_undamped - a.k_undamped.transpose()).norm();
  require(asym <= 1e-12 * a.k_undamped.norm(),
          fmt::format("FeModel::natural_frequencies_hz: Re K is not symmetric (‖K − Kᵀ‖ = {}); "
                      "a joint with non-symmetric Re K has no real modes",
                      asym));
  // The solver factors M by Cholesky without reporting failure, so check it first.
  if (Eigen::LLT<Eigen::MatrixXd>(a.m_dense).info() != Eigen::Success)
    throw std::runtime_error("FeModel::natural_frequencies_hz: mass matrix not positive definite (a DOF without mass?)");
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(a.k_undamped, a.m_dense, Eigen::EigenvaluesOnly);
  if (es.info() != Eigen::Success)
    throw std::runtime_error("FeModel::natural_frequencies_hz: the generalised eigensolver did not converge");
  std::vector<double> f;
  for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i) f.push_back(std::sqrt(std::max(es.eigenvalues()(i), 0.0)) / kTwoPi);
  std::sort(f.begin(), f.end());
  return f;
}

}  // namespace fe_oracle
