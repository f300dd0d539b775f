// toolpoint: stability of linear time-periodic delay equations by full-discretization — the
// kernel under the milling stability lobes (stability.hpp), exposed on its own so that it can be
// checked against published results for other delay equations.
//
// The equation, in input–output form (period T equal to the delay τ):
//     ẋ(t) = A₀ x(t) + B u(t),   u(t) = σ [P(t) C x(t) + Q(t) C x(t − τ) + w(t)],
// x ∈ ℝⁿ the state, A₀ constant and block diagonal, C (d × n) the d outputs the feedback reads,
// B (n × d) where it acts, P(t) and Q(t) (d × d) T-periodic and smooth between breakpoints, σ a
// scalar gain (the axial depth of cut in milling), w(t) (d) an optional T-periodic forcing. Milling:
// x the modal coordinates and their velocities, C x the tool-tip displacement, u the cutting force,
// P = −Q = ½K_t A(t) (the regenerative form: u depends on C x(t) − C x(t − τ) only), w the force
// per unit depth of the static chip (the feed). The forcing leaves the multipliers alone; it gives
// the map an affine part, x_{period} = Φ x₀ + q, whose fixed point x* = (I − Φ)⁻¹ q is the periodic
// (forced, chatter-free) motion of a stable cut (Insperger & Stépán, Semi-Discretization for
// Time-Delay Systems, Springer 2011, §5.3, surface location error).
//
// Discretization (m steps of h = T/m; full-discretization in the sense of Ding, Ding & Zhu,
// IJMTM 50 (2010) 502–509: only the constant part is exponentiated, so nothing depends on σ but
// a d × d solve per step): over each step the variation of constants formula
//     x_{k+1} = e^{A₀h} x_k + ∫₀ʰ e^{A₀(h−s)} B u(t_k + s) ds
// is evaluated with P(t), Q(t) exact (Gauss–Legendre quadrature split at the breakpoints, as
// semi-discretization integrates its interval averages exactly) and the outputs y = C x — current
// and delayed — replaced by their Lagrange interpolant of degree p through the samples
// y_{k+1−p} … y_{k+1} (and the same samples one period earlier). The newest sample y_{k+1} is
// implicit; it is found by a d × d solve. p = 1 interpolates linearly: for constant P, Q this is
// the first-order semi-discretization of Insperger & Stépán (Semi-Discretization for Time-Delay
// Systems, Springer 2011, §3), the same map. Errors fall like h^{p+1} (observed in the tests).
//
// Further delays (variable-pitch milling, whose teeth each have their own delay; the period is then
// a revolution): terms Q_j(t) C x(t − τ_j) with 0 < τ_j ≤ T, the delayed outputs interpolated by the
// same degree-p Lagrange polynomial through the samples around t − τ_j (τ_j need not be a whole
// number of steps: the polynomial is evaluated off its nodes, at s − f_j h with f_j the fractional
// part of τ_j/h). A τ_j within 1e-9 steps of a whole number is taken as that number, so a delay of
// T/N with m divisible by N gives exactly the map of N tooth periods (tests/periodic_delay_test).
//
// Only outputs are delayed: the map over one period acts on x₀ and the d-vectors y_{−1} …
// y_{−(m+p−1)}, and of those only the samples some step reads with a non-zero weight (at low
// radial immersion most steps are out of the cut). Dropped samples are exactly zero multipliers.
//
// Semi-discretization (Discretization::Semi; Insperger & Stépán, IJNME 55 (2002) 503–518 and
// 61 (2004) 117–141; first order: Insperger, Stépán & Turi, JSV 313 (2008) 334–341; docs/reference.md
// §13): the same steps, samples and buffer, but over step k the coefficients are their averages
// P̄_k = (1/h)∫ P, Q̄_k = (1/h)∫ Q, Q̄_jk, and the current term is exponentiated with A₀:
//     x_{k+1} = e^{A_k h} x_k + σ Σ_j Σ_{o=0,1} W_{jo} y_{k+o−i_j},   A_k = A₀ + σ B P̄_k C,
// the delayed output y(t_k + s − τ_j) replaced by the line through y_{k−i_j}, y_{k+1−i_j} taken at
// s − f_j h (first order) or at the step's midpoint h/2 − f_j h (zeroth order, constant over the
// step): with Γ₀ = ∫₀ʰ e^{A_k(h−s)} ds, Γ₁ = ∫₀ʰ e^{A_k(h−s)} s ds,
//     first:  W_{j0} = ((1 + f_j)Γ₀ − Γ₁/h) B Q̄_jk,  W_{j1} = (Γ₁/h − f_j Γ₀) B Q̄_jk;
//     zeroth: W_{j0} = (½ + f_j) Γ₀ B Q̄_jk,          W_{j1} = (½ − f_j) Γ₀ B Q̄_jk
// (the regenerative delay τ = T: i = m, f = 0, Q̄ = −P̄). e^{A_k h}, Γ₀, Γ₁ come from one matrix
// exponential of [[A_k, I, 0], [0, 0, I], [0, 0, 0]] h (Van Loan). They depend on σ: they are
// computed for the σ of the latest call and kept (one set per map, shared safely between threads).
#pragma once

#include <Eigen/Core>
#include <complex>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

namespace toolpoint {

// One further delayed term Q_j(t) C x(t − τ_j) of PeriodicDelaySystem (multiplied by σ like the others).
struct DelayedTerm {
  double delay = 0.0;  // τ_j [s], h ≤ τ_j ≤ T (h the step of the map built from the system)
  // Q_j(t) for t in [0, T): writes the d × d matrix into `out` (arrives sized d × d and zeroed).
  std::function<void(double t, Eigen::MatrixXd& out)> coefficient;
};

struct PeriodicDelaySystem {
  std::vector<Eigen::MatrixXd> a0_blocks;  // A₀ = diag(blocks), each square; n = Σ sizes
  Eigen::MatrixXd input;                   // B, n × d
  Eigen::MatrixXd output;                  // C, d × n
  double period = 0.0;                     // T = τ > 0 [s]
  // P(t), Q(t) for t in [0, T): the function writes the d × d matrix into `out`, which arrives
  // sized d × d and zeroed (so a function may leave it untouched where the coefficient is zero).
  // An empty function stands for zero. Called a few times per step when a map is built.
  std::function<void(double t, Eigen::MatrixXd&out)> current, delayed;
  // w(t) for t in [0, T): writes the d-vector into `out` (arrives sized d and zeroed). Empty: none.
  std::function<void(double t, Eigen::VectorXd& out)> forcing;
  bool regenerative = false;        // Q = −P: `delayed` is not used
  std::vector<DelayedTerm> delays;  // further delayed terms (not part of `regenerative`'s Q = −P)
  std::vector<double> breakpoints;  // times in (0, T) where P or Q jump
  // Throws InvalidArgument naming the member: sizes that disagree, T ≤ 0, non-finite entries, a
  // block of A₀ that is not diagonalisable with a condition number below 1e8.
  void check() const;
};

// The system with a velocity feedback added: u(t) += σ V(t) C_v x(t), C_v (d × n) reading the
// velocities the feedback acts on, V(t) (d × d) T-periodic (process damping: the flank's contact
// force −C_i b ṙ_n/V, Budak & Tunç, CIRP Annals 58 (2009) 403, b = σ). Built within the same form:
// the outputs become (C x, C_v x) (2d rows), the inputs (u, 0) with B' = [B, 0], and
//     P' = [[P, V], [0, 0]],  Q' = [[Q, 0], [0, 0]],  Q'_j = [[Q_j, 0], [0, 0]],  w' = (w, 0),
// a regenerative system becoming one with Q = −P written out (the velocity is not delayed). The
// map then carries 2d outputs per buffered sample: about twice the work. Throws InvalidArgument
// (C_v of the wrong size, an empty V, a bad system).
PeriodicDelaySystem with_velocity_feedback(const PeriodicDelaySystem& system, const Eigen::MatrixXd& velocity_output,
                                           std::function<void(double t, Eigen::MatrixXd& out)> feedback);

// The dominant Floquet multiplier of the period map (largest modulus; of a complex pair the one
// with Im ≥ 0) and its eigenvector (the reduced state, see PeriodMap::size).
struct DominantMultiplier {
  double spectral_radius = 0.0;
  std::complex<double> multiplier;
  Eigen::VectorXcd vector;  // empty when not asked for
  bool krylov = false;      // found by the Arnoldi iteration (else: dense eigen-decomposition)
};

// How each step's transition is built (see the header comment).
enum class Discretization {
  Full,  // full-discretization: only A₀ exponentiated, outputs interpolated (degree 1…3)
  Semi,  // semi-discretization: averaged coefficients, A₀ + σBP̄C exponentiated (order 0 or 1)
};

// The discretized period map of a PeriodicDelaySystem at m steps and degree p. Construction does
// every σ-independent piece of work (e^{A₀h}, the weights ∫ e^{A₀(h−s)} B P ℓ_j ds); applying the
// map at a gain σ is O(m n d) per vector.
class PeriodMap {
 public:
  // Throws InvalidArgument (bad system, steps outside 2…100000, degree outside 1…3 (Full) or 0…1
  // (Semi: the order of the delayed term's approximation)).
  PeriodMap(const PeriodicDelaySystem& system, int steps, int degree = 2, Discretization scheme = Discretization::Full);

  int size() const { return static_cast<int>(n_ + d_ * read_.size()); }  // the reduced state
  int steps() const { return m_; }
  int degree() const { return semi_.empty() ? p_ : semi_order_; }
  Discretization scheme() const { return semi_.empty() ? Discretization::Full : Discretization::Semi; }

  // v = Φ(σ) u for the reduced state (sizes: size()). Scalar: double or std::complex<double>.
  void apply(double sigma, const double* u, double* v) const;
  void apply(double sigma, const std::complex<double>* u, std::complex<double>* v) const;
  // The outputs y_0 … y_m over the period that starts from u (d × (m + 1)), complex.
  Eigen::MatrixXcd outputs(double sigma, const Eigen::VectorXcd& u) const;
  // The dense period map (size() × size()).
  Eigen::MatrixXd matrix(double sigma) const;
  // With PeriodicDelaySystem::forcing: the periodic solution, the fixed point u* = (I − Φ(σ))⁻¹ q(σ)
  // of the affine map (q: one period from rest under the forcing), and its outputs y_0 … y_m over
  // the period (d × (m + 1)). Throws InvalidArgument without forcing or with Discretization::Semi
  // (not implemented there), NumericalError when I − Φ is singular (a multiplier at 1).
  struct PeriodicSolution {
    Eigen::VectorXd state;
    Eigen::MatrixXd outputs;
  };
  PeriodicSolution periodic_solution(double sigma) const;
  // Its spectral radius and dominant multiplier: Arnoldi on apply() (no matrix is formed), the
  // dense eigen-decomposition for small maps or when Arnoldi does not converge (Spectra). Throws
  // NumericalError when neither converges or the multipliers are not finite.
  // `vector` false: the eigenvector is left empty (the dense path then skips computing it).
  DominantMultiplier dominant(double sigma, bool vector = true) const;
  double spectral_radius(double sigma) const { return dominant(sigma, false).spectral_radius; }

 private:
  template <typename S>
  void run(double sigma, int cols, const S* u, S* v, S* outputs) const;
  template <typename S>
  void run_one(double sigma, const S* u, S* v, S* outputs, bool forced = false) const;

  int n_ = 0, d_ = 0, m_ = 0, p_ = 0;
  bool regenerative_ = false;
  std::vector<int> block_start_, block_size_;
  std::vector<double> phi_;   // e^{A₀h} blocks, row-major, concatenated
  Eigen::MatrixXd c_;         // C (d × n)
  std::vector<char> active_;  // step k has non-zero weights
  // Per active step k, per node o = 0…p (sample y_{k+1−p+o}): W^P (n × d, column-major) and,
  // unless regenerative, W^Q; and the implicit factor (I − σ C W^P_p) parts C W^P_p, C W^Q_p.
  std::vector<std::vector<double>> wp_, wq_;
  // Further delays (PeriodicDelaySystem::delays): per delay j the whole steps i_j of τ_j = (i_j + f_j)h;
  // per active step the weights of each delay it reads, (p + 1) n × d column-major blocks.
  struct DelayWeights {
    int whole_steps = 0;
    std::vector<double> w;
  };
  std::vector<std::vector<DelayWeights>> wd_;
  std::vector<Eigen::MatrixXd> cwp_;           // C W^P for the newest node, d × d
  std::vector<Eigen::VectorXd> wf_;            // per step: ∫ e^{A₀(h−s)} B w(t_k + s) ds (n), empty without forcing
  std::vector<int> read_;                      // buffer samples y_{−i} kept in the reduced state (i ≥ 1)
  std::vector<int> slot_;                      // slot_[i]: position of y_{−i} in the reduced state, or −1
  std::vector<int> jump_;                      // jump_[k] ≥ 2: steps k… are free motion with no output read
  std::vector<std::vector<double>> jump_phi_;  // e^{A₀ jump_[k] h} blocks for such k

  // Semi-discretization (empty when Full): per step the averaged coefficients of each delayed term
  // (the period's first when read, then the further delays), P̄_k, and the step matrices at a σ.
  struct SemiDelay {
    int whole_steps = 0;
    double fraction = 0.0;
    Eigen::MatrixXd q;  // Q̄_jk (d × d)
  };
  struct SemiStep {
    Eigen::MatrixXd p;  // P̄_k (d × d)
    std::vector<SemiDelay> delays;
  };
  struct SemiMatrices {
    double sigma = 0.0;
    std::vector<Eigen::MatrixXd> phi;             // per active step: e^{A_k h} (n × n)
    std::vector<std::vector<Eigen::MatrixXd>> w;  // per active step: W_{j0}, W_{j1} per delay (n × d)
  };
  struct SemiCache {  // the matrices at the latest σ
    std::mutex mutex;
    std::shared_ptr<const SemiMatrices> latest;
  };
  std::shared_ptr<const SemiMatrices> semi_matrices(double sigma) const;
  template <typename S, typename Sample>
  void semi_step(const SemiMatrices& sm, int k, double sigma, std::size_t nc, const S* y, S* z, const Sample& sample) const;
  void build_semi(const PeriodicDelaySystem& sys, double h, const std::vector<int>& whole_steps,
                  const std::vector<double>& fraction);
  std::vector<SemiStep> semi_;
  int semi_order_ = 1;
  Eigen::MatrixXd a0_, b_;  // A₀ (n × n), B (n × d)
  double h_ = 0.0;          // the step [s]
  std::shared_ptr<SemiCache> semi_cache_;
};

}  // namespace toolpoint
