#include "physik/engine/linear_modes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <Eigen/Eigenvalues>

#include "physik/engine/mode_operators.h"

namespace physik {

namespace {

using Op = ModeOperators::Matrix;

constexpr double kZeroModeFraction = 1e-9;    // w^2 below this of the largest: a zero mode
constexpr double kUnreachedFraction = 1e-12;  // phi^T D1 phi below this of D1's scale
constexpr double kBreakdown = 1e-13;          // F q's part left after orthogonalisation
constexpr double kExhausted = 1e-6;           // a fresh F r's part left: range(F) is spanned
constexpr double kResidualPerGap = 1e-10;     // accepted residual, per unit distance to the others
constexpr double kResidualFloor = 1e-13;      // accepted residual at any distance
constexpr double kMaxNullPart = 1e6;          // null(K) round-off in a basis vector (below)
constexpr int kShiftProbeSteps = 8;           // steps before the shift is judged
constexpr int kMaxRuns = 16;                  // Lanczos runs (restarts + 1)
constexpr double kMaxBasisDoubles = 4e6;      // about 32 MB of basis vectors (q, K q, F q)
constexpr int kMaxBasis = 300;
// The count's floor, per w^2_max: there the zero modes' round-off in the count's pivots (of
// K - sigma M with K / sigma ~ 1e9 M at the zero-mode threshold) is far below sigma; measured
// on the shipped scenes: wrong counts up to 1e-9 w^2_max, right from 1e-8.
constexpr double kCountFloor = 1e-6;

// One Lanczos search for the slowest constrained mode (linear_modes.h). The basis and scratch
// vectors are the workspace's (mode_operators.h): pools grown on demand, never shrunk.
class SlowestModeSearch {
 public:
  explicit SlowestModeSearch(ModeOperators& ops) : ops_(ops), ws_(ops.workspace()), rng_(0x5eed) {
    const int nv = ops.size();
    cap_ =
        std::max(8, std::min({nv + 1, kMaxBasis, static_cast<int>(kMaxBasisDoubles / (3 * nv))}));
  }
  LinearModes run();

 private:
  bool search();
  bool certified();
  void walk();
  double next_mode(int below, double lo, int* multiplicity);
  int count_below(double sigma) {
    out_.counts += 1;
    return ops_.count_below(sigma);
  }
  enum class Kind { kZero, kSkipped, kFound };
  struct Mode {  // one Ritz pair under the rule
    Kind kind = Kind::kZero;
    double w2 = 0.0, d1 = 0.0, dr = 0.0, c = 0.0;
    bool converged = true;
  };
  enum class Stop { kNone, kRestart };
  bool lanczos(const VecX& start);
  Stop extend();
  void apply_f(const VecX& Kq, VecX& u);
  double orthogonalise(VecX& w, VecX& Kw, double* coefficient_on_last, double* norm_before);
  void append(VecX& w, VecX& Kw, double norm);
  bool null_part_grown();
  bool judge();
  double residual(int k) const;
  Mode evaluate(const VecX& y) const;
  void purified_ritz_vector(int k, VecX& y) const;
  bool conclude(const Mode* found);
  void lock(VecX& y, const Mode& mode);
  bool shift_far() const;
  void plan_restart();
  void random_vector(VecX& r);
  double count_floor() const { return std::max(threshold_, kCountFloor * w2_top_); }
  double lambda_of(double theta) const {
    const double t = std::min(theta, 1.0 - std::numeric_limits<double>::epsilon());
    return ops_.shift() * t / (1.0 - t);
  }

  ModeOperators& ops_;
  ModeWorkspace& ws_;
  std::mt19937_64 rng_;
  int cap_ = 0;
  int m_ = 0;                                    // basis vectors in use: ws_.basis[0 .. m_)
  std::vector<double> alpha_, beta_;             // T: diagonal, and beta_[j] between q_j and q_j+1
  std::vector<std::pair<int, double>> dropped_;  // breakdowns: step j and the beta_j left out
  bool exhausted_ = false;                       // range(F) spanned: every constrained mode is in T
  Eigen::VectorXd theta_;                        // Ritz values of the last judge(), ascending
  Eigen::MatrixXd ritz_;                         // and their vectors in the basis (m x m)
  std::vector<Mode> walked_;                     // the last judge()'s bottom pairs: zero or skipped
  double threshold_ = 0.0;                       // the zero-mode threshold, w^2
  double w2_top_ = 0.0;                          // the largest Ritz value so far, w^2
  int locked_ = 0;                               // locked modes: ws_.locked[0 .. locked_)
  std::vector<Mode> locked_modes_;
  double next_shift_ = 0.0;         // a restart's shift (its start: ws_.start)
  std::vector<double> skipped_w2_;  // the answer's skipped modes, w^2
  LinearModes out_;
};

void SlowestModeSearch::random_vector(VecX& r) {
  r.resize(ops_.size());
  // raw 53-bit draws: the same numbers on every platform (the distributions are not specified)
  for (int i = 0; i < r.size(); ++i) r[i] = 2.0 * static_cast<double>(rng_() >> 11) * 0x1p-53 - 1.0;
}

// u = F q = (K + s M)^-1 K q from K q
void SlowestModeSearch::apply_f(const VecX& Kq, VecX& u) {
  ops_.solve(Kq, u);
  out_.iterations += 1;
}

// classical Gram-Schmidt twice in the K inner product against the locked modes and the basis;
// returns ||w||_K and leaves K w in Kw
double SlowestModeSearch::orthogonalise(VecX& w, VecX& Kw, double* on_last, double* norm_before) {
  if (on_last) *on_last = 0.0;
  ops_.multiply(Op::kStiffness, w, Kw);
  if (norm_before) *norm_before = std::sqrt(std::max(w.dot(Kw), 0.0));
  for (int pass = 0; pass < 2; ++pass) {
    for (int i = 0; i < locked_; ++i) w.noalias() -= ws_.locked_k[i].dot(w) * ws_.locked[i];
    double h_last = 0.0;
    for (int i = 0; i < m_; ++i) {
      h_last = ws_.basis_k[i].dot(w);
      w.noalias() -= h_last * ws_.basis[i];
    }
    if (on_last && m_ > 0) *on_last += h_last;
  }
  ops_.multiply(Op::kStiffness, w, Kw);
  return std::sqrt(std::max(w.dot(Kw), 0.0));
}

// w / norm as the next basis vector, with its K and F images
void SlowestModeSearch::append(VecX& w, VecX& Kw, double norm) {
  w /= norm;
  Kw /= norm;
  if (static_cast<int>(ws_.basis.size()) == m_) {
    ws_.basis.emplace_back();
    ws_.basis_k.emplace_back();
    ws_.basis_f.emplace_back();
  }
  ws_.basis[m_] = w;
  ws_.basis_k[m_] = Kw;
  apply_f(ws_.basis_k[m_], ws_.basis_f[m_]);
  ++m_;
}

// Has the round-off on null(K) grown in the newest basis vector q (K-normalised)? Its part in
// range(F) has ||r||_M >= 1 / w_max, so its entries lose relative precision eps ||q||_M w_max
// at most: past kMaxNullPart (1e-10 / eps) the run restarts from purified vectors.
bool SlowestModeSearch::null_part_grown() {
  ops_.multiply(Op::kMass, ws_.basis[m_ - 1], ws_.my);
  const double w2_max = std::max(ops_.shift(), w2_top_);
  return std::sqrt(ws_.basis[m_ - 1].dot(ws_.my) * w2_max) > kMaxNullPart;
}

// one Lanczos step: alpha_j, beta_j and q_j+1 (or, after a breakdown, a fresh direction, or
// exhausted_)
SlowestModeSearch::Stop SlowestModeSearch::extend() {
  double a = 0.0, before = 0.0;
  VecX& w = ws_.w;
  w = ws_.basis_f[m_ - 1];
  const double beta = orthogonalise(w, ws_.kw, &a, &before);
  alpha_.push_back(a);
  if (beta > kBreakdown * before) {
    beta_.push_back(beta);
    append(w, ws_.kw, beta);
  } else {
    // an invariant subspace: go on from a fresh direction in range(F), if there is one left;
    // the beta left out of T still counts in the residuals
    beta_.push_back(0.0);
    dropped_.emplace_back(static_cast<int>(alpha_.size()) - 1, beta);
    random_vector(ws_.ay);
    ops_.multiply(Op::kStiffness, ws_.ay, ws_.kw);
    apply_f(ws_.kw, w);
    double z_norm = 0.0;
    const double left = orthogonalise(w, ws_.kw, nullptr, &z_norm);
    if (left <= kExhausted * z_norm) {
      exhausted_ = true;
      return Stop::kNone;
    }
    append(w, ws_.kw, left);
  }
  return m_ <= cap_ && !null_part_grown() ? Stop::kNone : Stop::kRestart;
}

// the Ritz vector of pair k, purified: F (Q s) / theta = (U s) / theta, which has no part on
// null(K) whatever the basis carries there (the Ericsson-Ruhe purification); unnormalised
void SlowestModeSearch::purified_ritz_vector(int k, VecX& y) const {
  y.setZero(ops_.size());
  for (int i = 0; i < ritz_.rows(); ++i) y.noalias() += ritz_(i, k) * ws_.basis_f[i];
}

// the rule on a converged Ritz vector: its w^2 and quadratic forms by Rayleigh quotients
SlowestModeSearch::Mode SlowestModeSearch::evaluate(const VecX& y) const {
  Mode m;
  ops_.multiply(Op::kMass, y, ws_.my);
  const double norm2 = y.dot(ws_.my);
  ops_.multiply(Op::kStiffness, y, ws_.ay);
  m.w2 = y.dot(ws_.ay) / norm2;
  if (m.w2 <= threshold_) return m;
  ops_.multiply(Op::kEndDampers, y, ws_.ay);
  m.d1 = y.dot(ws_.ay) / norm2;
  ops_.multiply(Op::kFactorDamper, y, ws_.ay);
  m.dr = y.dot(ws_.ay) / norm2;
  m.c = (2.0 * std::sqrt(m.w2) - m.dr) / m.d1;
  const bool unreached = m.d1 <= kUnreachedFraction * ops_.end_damper_scale();
  m.kind = unreached || m.c <= 0.0 ? Kind::kSkipped : Kind::kFound;
  return m;
}

// ||F y - theta y||_K of Ritz pair k: beta_m |s_m|, and the betas left out at breakdowns
double SlowestModeSearch::residual(int k) const {
  const int m = static_cast<int>(ritz_.rows());
  double r2 = exhausted_ ? 0.0 : std::pow(beta_[m - 1] * ritz_(m - 1, k), 2);
  for (const auto& [j, b] : dropped_) r2 += std::pow(b * ritz_(j, k), 2);
  return std::sqrt(r2);
}

// Ritz pairs of T, walked in ascending order under the rule; true when the answer is final
bool SlowestModeSearch::judge() {
  const int m = static_cast<int>(alpha_.size());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig;
  const Eigen::VectorXd diag = Eigen::Map<const Eigen::VectorXd>(alpha_.data(), m);
  const Eigen::VectorXd sub = Eigen::Map<const Eigen::VectorXd>(beta_.data(), m - 1);
  eig.computeFromTridiagonal(diag, sub, Eigen::ComputeEigenvectors);
  theta_ = eig.eigenvalues();
  ritz_ = eig.eigenvectors();
  w2_top_ = std::max(w2_top_, lambda_of(theta_[m - 1]));
  threshold_ = kZeroModeFraction * w2_top_;
  walked_.clear();
  for (int k = 0; k < m; ++k) {
    // the distance to the other Ritz values (F's spectrum lies in [0, 1)); a lone Ritz value
    // before range(F) is spanned has none, and only the floor accepts it: the start vector was
    // filtered by F at a shift near the stiff end (mu = w^2 / (w^2 + s)), which can leave a
    // slow mode's part in it, and in the first residual, below the test (a long chain's
    // translation along itself), so the stiff Ritz value would pass for the slowest mode and
    // the count would then send the search on the walk
    double gap = m > 1 || exhausted_ ? 1.0 : 0.0;
    if (k > 0) gap = theta_[k] - theta_[k - 1];
    if (k + 1 < m) gap = std::min(gap, theta_[k + 1] - theta_[k]);
    const bool converged = residual(k) <= std::max(kResidualPerGap * gap, kResidualFloor);
    if (lambda_of(theta_[k]) <= threshold_) {  // below the true one's: a zero mode either way
      walked_.push_back(Mode{Kind::kZero, lambda_of(theta_[k]), 0.0, 0.0, 0.0, converged});
      continue;
    }
    if (!converged) return false;
    purified_ritz_vector(k, ws_.w);
    const Mode mode = evaluate(ws_.w);
    if (mode.kind == Kind::kFound) return conclude(&mode);
    walked_.push_back(mode);
  }
  return exhausted_ && conclude(nullptr);
}

// the answer from the locked modes, the walked ones and the one found (if any)
bool SlowestModeSearch::conclude(const Mode* found) {
  LinearModes out;
  out.omega2_max = w2_top_;
  double first = std::numeric_limits<double>::infinity();
  skipped_w2_.clear();
  for (const std::vector<Mode>* list : {&locked_modes_, &walked_}) {
    for (const Mode& m : *list) {
      if (m.kind != Kind::kSkipped || (found && m.w2 > found->w2)) continue;
      first = std::min(first, m.w2);
      skipped_w2_.push_back(m.w2);
      ++out.skipped;
    }
  }
  if (found) {
    first = std::min(first, found->w2);
    out.found = true;
    out.slowest_omega = std::sqrt(found->w2);
    out.slowest_d1 = found->d1;
    out.slowest_dr = found->dr;
    out.critical_damping = found->c;
  }
  out.first_constrained_omega = std::isfinite(first) ? std::sqrt(first) : 0.0;
  out.iterations = out_.iterations;
  out.runs = out_.runs;
  out.counts = out_.counts;
  out_ = out;
  return true;
}

// keeps y (a converged mode the rule skipped) out of later runs' Krylov spaces
void SlowestModeSearch::lock(VecX& y, const Mode& mode) {
  if (static_cast<int>(ws_.locked.size()) == locked_) {
    ws_.locked.emplace_back();
    ws_.locked_k.emplace_back();
  }
  const int saved = m_;
  m_ = 0;  // against the locked ones only
  const double norm = orthogonalise(y, ws_.kw, nullptr, nullptr);
  m_ = saved;
  if (!(norm > 0.0)) return;
  ws_.locked[locked_] = y / norm;
  ws_.locked_k[locked_] = ws_.kw / norm;
  ++locked_;
  locked_modes_.push_back(mode);
}

// after judge(): is the shift off the first Ritz value the walk has not passed by more than 4x
bool SlowestModeSearch::shift_far() const {
  const int k = static_cast<int>(walked_.size());
  if (k == theta_.size()) return false;
  const double w2 = lambda_of(theta_[k]);
  return ops_.shift() > 4.0 * w2 || ops_.shift() < 0.25 * w2;
}

// After judge(): lock the converged walked pairs (they would be found again), and plan the next
// run: its shift the first Ritz value the walk has not passed (the shift then sits at the next
// candidate's w^2, see the header), its start the sum of the next four purified Ritz vectors,
// each K-normalised
void SlowestModeSearch::plan_restart() {
  std::size_t open = 0;
  for (; open < walked_.size() && walked_[open].converged; ++open) {
    purified_ritz_vector(static_cast<int>(open), ws_.w);
    lock(ws_.w, walked_[open]);
  }
  next_shift_ = ops_.shift();
  if (static_cast<int>(open) == theta_.size()) {
    random_vector(ws_.start);
    return;
  }
  next_shift_ = std::max(lambda_of(theta_[open]), threshold_);
  ws_.start.setZero(ops_.size());
  for (int k = open; k < std::min<int>(open + 4, theta_.size()); ++k) {
    purified_ritz_vector(k, ws_.w);
    ops_.multiply(Op::kStiffness, ws_.w, ws_.ay);
    ws_.start += ws_.w / std::sqrt(ws_.w.dot(ws_.ay));
  }
}

// one run from F start at the current shift; true when the answer is final, false with a
// restart planned
bool SlowestModeSearch::lanczos(const VecX& start) {
  m_ = 0;
  alpha_.clear();
  beta_.clear();
  dropped_.clear();
  exhausted_ = false;
  out_.runs += 1;
  ops_.multiply(Op::kStiffness, start, ws_.kw);
  apply_f(ws_.kw, ws_.w);
  const double norm = orthogonalise(ws_.w, ws_.kw, nullptr, nullptr);
  if (!(norm > 0.0)) return conclude(nullptr);  // nothing left in range(F)
  append(ws_.w, ws_.kw, norm);
  while (true) {
    const Stop stop = extend();
    const int m = static_cast<int>(alpha_.size());
    if (exhausted_ || stop != Stop::kNone || m <= 24 || m % 8 == 0) {
      if (judge()) return true;
    }
    if (exhausted_ || stop == Stop::kRestart || (m == kShiftProbeSteps && shift_far())) {
      plan_restart();
      return false;
    }
  }
}

// Lanczos, its answer certified by two counts; the walk when it is not (or Lanczos did not
// converge)
LinearModes SlowestModeSearch::run() {
  if (ops_.stiffness_empty()) return out_;
  if (search() && certified()) return out_;
  if (w2_top_ > 0.0) walk();  // else K has nothing on a random vector: no constrained mode
  return out_;
}

// Every mode between the zero-mode threshold and the answer (all modes, when none is found)
// was seen: as many as the counts find there. A mode repeated in w (one Krylov vector per
// eigenspace) or one Lanczos missed fails this.
// Below the count's floor (kCountFloor) the count is not trusted, nor needed: an answer there is
// taken as it is.
bool SlowestModeSearch::certified() {
  const double floor = count_floor();
  const double found_w2 = out_.slowest_omega * out_.slowest_omega;
  if (out_.found && found_w2 <= floor) return true;
  int seen = out_.found ? 1 : 0;
  for (double w2 : skipped_w2_) seen += w2 > floor ? 1 : 0;
  const int below = count_below(floor);
  const int upto = out_.found ? count_below(found_w2 * (1.0 + 1e-9)) : ops_.size();
  return upto - below == seen;
}

// The first w^2 above lo, where count_below(lo) = below, by bisection on the count (to 1e-12
// relative; geometric while the bracket spans more than 4x); `multiplicity` the modes there
double SlowestModeSearch::next_mode(int below, double lo, int* multiplicity) {
  double hi = 4.0 * lo;
  int at_hi = count_below(hi);
  while (at_hi == below) {
    lo = hi;
    hi *= 4.0;
    at_hi = count_below(hi);
  }
  while (hi > lo * (1.0 + 1e-12)) {
    const double mid = hi > 4.0 * lo ? std::sqrt(lo * hi) : 0.5 * (lo + hi);
    const int at_mid = count_below(mid);
    if (at_mid > below) {
      hi = mid;
      at_hi = at_mid;
    } else {
      lo = mid;
    }
  }
  *multiplicity = at_hi - below;
  return lo;
}

// The rule's walk by counts: each mode above the count's floor in ascending order, w^2 by
// bisection, phi by inverse iteration (K - sigma M)^-1 M just below it (zero modes shrink by
// (w^2 - sigma) / sigma, about 1e-10, per step), until a mode is found. A repeated mode counts
// with its multiplicity. Modes between the zero-mode threshold and the floor are not walked.
void SlowestModeSearch::walk() {
  LinearModes out;
  out.omega2_max = w2_top_;
  out.iterations = out_.iterations;
  out.runs = out_.runs;
  out.counts = out_.counts;
  out.walked = true;
  out_ = out;
  double lo = count_floor();
  int below = count_below(lo);
  VecX& x = ws_.start;
  while (below < ops_.size()) {
    int multiplicity = 0;
    lo = next_mode(below, lo, &multiplicity);
    ops_.set_shift(-lo * (1.0 - 1e-10));
    random_vector(x);
    for (int k = 0; k < 4; ++k) {
      ops_.multiply(Op::kMass, x, ws_.my);
      ops_.solve(ws_.my, x);
      out_.iterations += 1;
      ops_.multiply(Op::kMass, x, ws_.my);
      x /= std::sqrt(x.dot(ws_.my));
    }
    const Mode mode = evaluate(x);
    if (out_.first_constrained_omega == 0.0) out_.first_constrained_omega = std::sqrt(mode.w2);
    below += multiplicity;
    lo *= 1.0 + 1e-12;
    if (mode.kind != Kind::kFound) {
      out_.skipped += multiplicity;
      continue;
    }
    out_.found = true;
    out_.slowest_omega = std::sqrt(mode.w2);
    out_.slowest_d1 = mode.d1;
    out_.slowest_dr = mode.dr;
    out_.critical_damping = mode.c;
    return;
  }
}

// the Lanczos runs (linear_modes.h); false when they did not converge
bool SlowestModeSearch::search() {
  // the first shift: the Rayleigh quotient of a vector in range(F) (F at the Rayleigh quotient
  // of a random vector, whose null(K) part pulls it below the constrained modes)
  VecX& r = ws_.start;
  random_vector(r);
  ops_.multiply(Op::kStiffness, r, ws_.kw);
  ops_.multiply(Op::kMass, r, ws_.my);
  const double rKr = r.dot(ws_.kw), rMr = r.dot(ws_.my);
  if (!(rKr > 0.0)) return false;
  ops_.set_shift(rKr / rMr);
  apply_f(ws_.kw, ws_.w);
  r = ws_.w;
  ops_.multiply(Op::kStiffness, r, ws_.kw);
  ops_.multiply(Op::kMass, r, ws_.my);
  ops_.set_shift(r.dot(ws_.kw) / r.dot(ws_.my));
  for (int run = 0; run < kMaxRuns; ++run) {
    if (lanczos(r)) return true;
    ops_.set_shift(next_shift_);
  }
  return false;
}

}  // namespace

LinearModes linear_modes(const Scene& scene, const SimState& state,
                         const std::vector<Vec3>& targets_world, ModeWorkspace& workspace) {
  ModeOperators ops(scene, state, targets_world, workspace);
  return SlowestModeSearch(ops).run();
}

LinearModes linear_modes(const Scene& scene, const SimState& state,
                         const std::vector<Vec3>& targets_world) {
  ModeWorkspace workspace;
  return linear_modes(scene, state, targets_world, workspace);
}

void update_auto_damping(const Scene& scene, SimState& s) {
  // the springs' stiffness of the settling approach: d = 0, so capped springs count with k 1
  // (beyond the cap they have none along the pull, and the whole-body translation would be a
  // zero mode at the start pose of a far target)
  std::vector<Vec3> at_target(scene.control_points.size());
  for (std::size_t c = 0; c < at_target.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    at_target[c] = point_on_bone(s.frames, cp.bone, cp.alpha);
  }
  s.damping_auto_value = linear_modes(scene, s, at_target, s.modes).critical_damping;
  s.damping_auto_updates += 1;
}

}  // namespace physik
