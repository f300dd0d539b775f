// toolpoint: spindle–holder–tool assembly by receptance coupling (seed Section 2.1).
#include "toolpoint/model/assembly.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "toolpoint/model/coupling.hpp"
#include "whirl_pole.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint {

namespace {
// Segment pieces shorter than this are rounding left-overs of a split, not geometry.
constexpr double kLengthEps = 1e-9;  // m
}  // namespace

// ---- Bearing, tool, assembly checks -------------------------------------------------------------

Block Bearing::dynamic_stiffness(double frequency_hz) const {
  const double w = omega_of(frequency_hz);
  return make_block({stiffness, w * damping}, 0.0, 0.0, {rotational_stiffness, w * rotational_damping});
}

Block Bearing::dynamic_stiffness_y(double frequency_hz) const {
  const double w = omega_of(frequency_hz);
  return make_block({stiffness_y.value_or(stiffness), w * damping_y.value_or(damping)}, 0.0, 0.0,
                    {rotational_stiffness, w * rotational_damping});
}

bool Bearing::isotropic() const { return (!stiffness_y || *stiffness_y == stiffness) && (!damping_y || *damping_y == damping); }

void Bearing::check() const {
  const std::string who = name.empty() ? std::string("bearing") : name;
  const double v[5] = {position, stiffness, damping, rotational_stiffness, rotational_damping};
  const char* keys[5] = {"position", "stiffness", "damping", "rotational_stiffness", "rotational_damping"};
  for (int i = 0; i < 5; ++i) {
    if (!std::isfinite(v[i])) throw InvalidArgument(fmt::format("{}: {} = {} is not finite", who, keys[i], v[i]));
    if (v[i] < 0.0) throw InvalidArgument(fmt::format("{}: {} = {} must be ≥ 0", who, keys[i], v[i]));
  }
  for (const auto& [value, key] : {std::pair{stiffness_y, "stiffness_y"}, std::pair{damping_y, "damping_y"}})
    if (value && !(std::isfinite(*value) && *value >= 0.0))
      throw InvalidArgument(fmt::format("{}: {} = {} must be ≥ 0", who, key, *value));
  for (std::size_t k = 0; k < speed_table.size(); ++k) {
    const BearingSpeedPoint& r = speed_table[k];
    const std::string row = fmt::format("{}: speed_table row {} ({} rpm)", who, k + 1, r.speed_rpm);
    if (!(std::isfinite(r.speed_rpm) && r.speed_rpm >= 0.0))
      throw InvalidArgument(fmt::format("{}: speed_rpm = {} must be ≥ 0", row, r.speed_rpm));
    if (!(std::isfinite(r.stiffness) && r.stiffness >= 0.0))
      throw InvalidArgument(fmt::format("{}: stiffness = {} N/m must be ≥ 0", row, r.stiffness),
                            "a bearing's stiffness is not negative; check the table's sign and units (N/m)");
    if (!(std::isfinite(r.damping) && r.damping >= 0.0))
      throw InvalidArgument(fmt::format("{}: damping = {} N·s/m must be ≥ 0", row, r.damping));
    if (k > 0 && !(r.speed_rpm > speed_table[k - 1].speed_rpm))
      throw InvalidArgument(fmt::format("{}: speeds must increase (after {} rpm)", row, speed_table[k - 1].speed_rpm),
                            "list the rows by increasing speed, each speed once");
  }
  if (!speed_table.empty() && (stiffness_y || damping_y))
    throw InvalidArgument(
        fmt::format("{}: a speed table applies to both directions; it cannot go with stiffness_y or damping_y", who));
  if (stiffness == 0.0 && damping == 0.0 && rotational_stiffness == 0.0 && rotational_damping == 0.0)
    throw InvalidArgument(fmt::format("{}: all stiffness and damping values are zero", who), "give at least `stiffness` in N/m");
}

void Tool::check() const {
  material.check();
  auto positive = [](double v, const char* key) {
    if (!std::isfinite(v) || !(v > 0.0)) throw InvalidArgument(fmt::format("tool.{} = {} m must be > 0", key, v));
  };
  positive(length, "length");
  positive(overhang, "overhang");
  if (overhang < 1e-4)
    throw InvalidArgument(fmt::format("tool.overhang = {} m: a tool must stick out at least 0.1 mm", overhang),
                          "overhangs are in metres (49 mm = 0.049)");
  positive(diameter, "diameter");
  if (shank_diameter < 0.0 || !std::isfinite(shank_diameter))
    throw InvalidArgument(fmt::format("tool.shank_diameter = {} m must be > 0", shank_diameter));
  if (flute_length < 0.0 || !std::isfinite(flute_length))
    throw InvalidArgument(fmt::format("tool.flute_length = {} m must be ≥ 0", flute_length));
  if (!(flute_diameter_ratio > 0.0 && flute_diameter_ratio <= 1.0))
    throw InvalidArgument(fmt::format("tool.flute_diameter_ratio = {} must lie in (0, 1]", flute_diameter_ratio),
                          "an equivalent fluted diameter is about 0.8 of the nominal one");
  if (overhang > length + kLengthEps)
    throw InvalidArgument(fmt::format("tool.overhang = {} m exceeds tool.length = {} m", overhang, length));
  if (flute_length > length + kLengthEps)
    throw InvalidArgument(fmt::format("tool.flute_length = {} m exceeds tool.length = {} m", flute_length, length));
}

std::vector<Segment> Tool::segments(ShearModel model) const {
  std::vector<Segment> s;
  const double fl = std::min(flute_length, length);
  auto add = [&](double len, double d, const char* what) {
    if (len <= kLengthEps) return;
    Segment seg = Segment::tube(len, d, 0.0, material, fmt::format("tool {}", what));
    seg.shear_model = model;
    seg.layers[0].shear_coefficient = shear_coefficient;
    s.push_back(std::move(seg));
  };
  add(fl, flute_diameter_ratio * diameter, "fluted part");
  add(length - fl, shank_diameter > 0.0 ? shank_diameter : diameter, "shank");
  return s;
}

namespace {

double total_length(const std::vector<Segment>& s) {
  double l = 0.0;
  for (const auto& x : s) l += x.length;
  return l;
}

// The section where the tool sits in the holder is composite (sleeve and tool bonded: EI, κGA, ρA,
// ρI add), which needs the tool to fill the bore: its shank, and its flutes on their lands (the
// nominal diameter; the fluted part's equivalent diameter is a stiffness, not a size). Fits and
// shrink-fit interferences are hundredths of a millimetre; a gap of more than 1 % of the bore is
// another part (a sleeve, a collet) or a slip. A bore narrower than the tool: insert_tool.
void check_tool_fills_bore(const std::vector<Segment>& holder, const Tool& tool) {
  constexpr double kBoreGap = 0.01;
  const double inside = tool.length - tool.overhang;
  const double flutes = std::min(tool.flute_length, tool.length);  // from the tool's tip
  const double shank = tool.shank_diameter > 0.0 ? tool.shank_diameter : tool.diameter;
  double depth = 0.0;  // of the segment's start from the holder tip
  for (const Segment& h : holder) {
    const double start = depth, end = std::min(depth + h.length, inside);
    depth += h.length;
    if (start >= inside - kLengthEps) break;
    double bore = std::numeric_limits<double>::infinity();
    for (const Annulus& l : h.layers) bore = std::min(bore, l.inner_diameter);
    if (!(bore > 0.0) || !std::isfinite(bore)) continue;  // no bore: insert_tool says so
    // The tool's parts in [start, end) from the holder tip: [overhang + start, overhang + end) from its tip.
    const bool has_flutes = tool.overhang + start < flutes - kLengthEps;
    const bool has_shank = tool.overhang + end > flutes + kLengthEps;
    const bool shank_narrower = has_shank && (!has_flutes || shank < tool.diameter);
    const double contact = shank_narrower ? shank : tool.diameter;
    if (contact < bore * (1.0 - kBoreGap))
      throw InvalidArgument(
          fmt::format("{}: its bore of {:.4g} mm holds the tool's {} of {:.4g} mm diameter ({}): a gap of {:.3g} mm, so the "
                      "two would not act as one section, as the model of the holder with the tool inside assumes",
                      h.name.empty() ? "holder segment" : h.name, 1e3 * bore, shank_narrower ? "shank" : "fluted part",
                      1e3 * contact, shank_narrower && tool.shank_diameter > 0.0 ? "tool.shank_diameter" : "tool.diameter",
                      1e3 * (bore - contact)),
          "give the holder segments the tool sits in the tool's diameter as their bore (inner_diameter; a shrink fit or "
          "collet grips it), or correct tool.shank_diameter; a reduction sleeve or collet is part of the holder "
          "(segments whose bore is the shank's)");
  }
}

}  // namespace

void Assembly::check() const {
  if (spindle.segments.empty()) throw InvalidArgument("spindle has no segments", "add [[spindle.segment]] tables");
  if (holder.empty()) throw InvalidArgument("holder has no segments", "add [[holder.segment]] tables");
  for (const auto& s : spindle.segments) s.check();
  for (const auto& s : holder) s.check();
  tool.check();
  const double ls = total_length(spindle.segments);
  for (const auto& b : spindle.bearings) {
    b.check();
    if (b.position > ls + kLengthEps)
      throw InvalidArgument(fmt::format("{}: position {} m lies beyond the spindle's rear end at {} m from the nose",
                                        b.name.empty() ? "bearing" : b.name, b.position, ls),
                            "bearing positions are measured from the spindle nose, inwards, in metres");
  }
  const double insertion = tool.length - tool.overhang;
  const double lh = total_length(holder);
  if (insertion > lh + kLengthEps)
    throw InvalidArgument(
        fmt::format("tool: {} m of the tool sits inside the holder (length − overhang) but the holder is only {} m long",
                    insertion, lh));
  check_tool_fills_bore(holder, tool);
  spindle_holder.parameters.check();
  holder_tool.parameters.check();
  if (method == ReceptanceMethod::Modal && (modal_terms < 1 || modal_terms > 20000))
    throw InvalidArgument(fmt::format("model.modal_terms = {} must lie in 1..20000", modal_terms));
  grid.check();
  (void)insert_tool(holder, split_segments(tool.segments(shear_model), tool.overhang).second);
}

// ---- Segment chains -----------------------------------------------------------------------------

std::pair<std::vector<Segment>, std::vector<Segment>> split_segments(const std::vector<Segment>& segments, double distance) {
  std::vector<Segment> outer, inner;
  double pos = 0.0;
  for (const Segment& s : segments) {
    const double start = pos, end = pos + s.length;
    pos = end;
    if (end <= distance + kLengthEps) {
      outer.push_back(s);
    } else if (start >= distance - kLengthEps) {
      inner.push_back(s);
    } else {
      Segment a = s, b = s;
      a.length = distance - start;
      b.length = end - distance;
      outer.push_back(std::move(a));
      inner.push_back(std::move(b));
    }
  }
  return {outer, inner};
}

std::vector<Segment> insert_tool(const std::vector<Segment>& holder, const std::vector<Segment>& tool_inside) {
  std::vector<Segment> out;
  const double inserted = total_length(tool_inside);
  if (inserted <= kLengthEps) return holder;
  std::vector<Segment> rest = holder;
  std::vector<Segment> tool_rest = tool_inside;
  double depth = 0.0;
  // Walk the holder; where the tool is inside, cut at each tool boundary and add the tool's layers.
  for (const Segment& t : tool_inside) {
    auto [outer, inner] = split_segments(rest, t.length);
    if (total_length(outer) < t.length - kLengthEps)
      throw InvalidArgument(fmt::format("the tool goes {} m deep into a holder only {} m long", inserted, total_length(holder)));
    for (Segment h : outer) {
      double bore = std::numeric_limits<double>::infinity();
      for (const Annulus& l : h.layers) bore = std::min(bore, l.inner_diameter);
      const double shank = t.layers.front().outer_diameter;
      if (bore <= 0.0)
        throw InvalidArgument(
            fmt::format("{}: solid (no bore) at {:.4g} m from the holder tip, but the tool is inserted {:.4g} m deep",
                        h.name.empty() ? "holder segment" : h.name, depth, inserted),
            "give the holder segments an inner_diameter (the bore) where the shank sits");
      if (shank > bore * (1.0 + 1e-9))
        throw InvalidArgument(fmt::format("{}: bore {} m is narrower than the tool part inside it ({} m diameter)",
                                          h.name.empty() ? "holder segment" : h.name, bore, shank));
      for (const Annulus& l : t.layers) h.layers.push_back(l);
      depth += h.length;
      out.push_back(std::move(h));
    }
    rest = std::move(inner);
  }
  for (Segment& h : rest) out.push_back(std::move(h));
  return out;
}

Chain::Chain(std::vector<Segment> pieces, ReceptanceMethod method, int modal_terms)
    : pieces_(std::move(pieces)), ground_(pieces_.size() + 1), method_(method), modal_terms_(modal_terms) {
  for (const Segment& s : pieces_) {
    s.check();
    props_.push_back(s.properties());
    if (method != ReceptanceMethod::Modal) continue;
    const SectionProperties& p = props_.back();
    // The modal sum damps every mode by one η: a composite section whose layers differ in loss
    // factor has no such η, so that piece is computed exactly (and said so).
    const double eta_b = p.EI.imag() / p.EI.real(), eta_s = p.kGA.imag() / p.kGA.real();
    if (std::abs(eta_b - eta_s) > 1e-12 * std::max(1.0, std::abs(eta_b))) {
      warnings_.push_back(
          fmt::format("{}: its layers have different loss factors, which the modal method cannot represent; "
                      "this piece uses the exact solution",
                      s.name.empty() ? "segment" : s.name));
      modal_.push_back(nullptr);
      continue;
    }
    modal_.push_back(std::make_shared<const ModalBeam>(p, s.length, ModalOptions{modal_terms, true}));
  }
}

void Chain::add_ground(std::size_t node, const Bearing& b) {
  if (node >= ground_.size())
    throw InvalidArgument(fmt::format("ground node {} outside the chain's {} nodes", node, ground_.size()));
  ground_[node].push_back(b);
}

double Chain::length() const { return total_length(pieces_); }

bool Chain::has_modal_pieces() const {
  return std::any_of(modal_.begin(), modal_.end(), [](const auto& m) { return m != nullptr; });
}

TwoPort Chain::piece(std::size_t i, double frequency_hz) const {
  return modal_.empty() || !modal_[i] ? exact_receptance(props_[i], pieces_[i].length, frequency_hz)
                                      : modal_[i]->receptance(frequency_hz);
}

TwoPort Chain::piece(std::size_t i, double frequency_hz, double spin_rad_s, Whirl whirl, SectionWaves& waves,
                     const SectionProperties*& waves_of) const {
  if (!modal_.empty() && modal_[i]) {
    if (spin_rad_s != 0.0)
      throw InvalidArgument("a spinning assembly needs Assembly::method exact: the whirls' receptances are exact only",
                            "use the exact method (the default)");
    return modal_[i]->receptance(frequency_hz);
  }
  const SectionProperties& p = props_[i];
  if (!waves_of || !(*waves_of == p)) {
    // At spin 0 whirl_rotary_inertia is ρI exactly: the standing waves.
    waves = spin_rad_s == 0.0 ? section_waves(p, frequency_hz) : section_waves(p, frequency_hz, spin_rad_s, whirl);
    waves_of = &p;
  }
  return exact_receptance(waves, pieces_[i].length);
}

namespace {

bool ground_at(const std::vector<Bearing>& node, double f, Block& D) {
  if (node.empty()) return false;
  D = Block::Zero();
  for (const Bearing& b : node) D += b.dynamic_stiffness(f);
  return true;
}

// Both planes: diag(D_x, D_y).
bool ground_at(const std::vector<Bearing>& node, double f, Block4& D) {
  if (node.empty()) return false;
  D = Block4::Zero();
  for (const Bearing& b : node) {
    D.topLeftCorner<2, 2>() += b.dynamic_stiffness(f);
    D.bottomRightCorner<2, 2>() += b.dynamic_stiffness_y(f);
  }
  return true;
}

}  // namespace

TwoPort Chain::two_port(double f) const { return two_port(f, 0.0, Whirl::Forward); }

Block Chain::point(double f) const { return point(f, 0.0, Whirl::Forward); }

TwoPort Chain::two_port(double f, double spin_rad_s, Whirl whirl) const {
  if (pieces_.empty()) throw InvalidArgument("empty segment chain");
  const std::size_t n = pieces_.size();
  Block D;
  SectionWaves waves;
  const SectionProperties* waves_of = nullptr;
  TwoPort g = piece(n - 1, f, spin_rad_s, whirl, waves, waves_of);
  if (ground_at(ground_[n], f, D)) g = ground_end2(g, D);
  for (std::size_t k = n - 1; k-- > 0;) {
    if (ground_at(ground_[k + 1], f, D)) g = ground_end1(g, D);
    g = couple_rigid(piece(k, f, spin_rad_s, whirl, waves, waves_of), g);
  }
  if (ground_at(ground_[0], f, D)) g = ground_end1(g, D);
  return g;
}

Block Chain::point(double f, double spin_rad_s, Whirl whirl) const {
  if (pieces_.empty()) throw InvalidArgument("empty segment chain");
  const std::size_t n = pieces_.size();
  Block D;
  SectionWaves waves;
  const SectionProperties* waves_of = nullptr;
  TwoPort last = piece(n - 1, f, spin_rad_s, whirl, waves, waves_of);
  if (ground_at(ground_[n], f, D)) last = ground_end2(last, D);
  Block g = last.b11;
  for (std::size_t k = n - 1; k-- > 0;) {
    if (ground_at(ground_[k + 1], f, D)) g = ground_point(g, D);
    g = couple_rigid_point(piece(k, f, spin_rad_s, whirl, waves, waves_of), g);
  }
  if (ground_at(ground_[0], f, D)) g = ground_point(g, D);
  return g;
}

Block4 Chain::point_two_plane(double f, double spin_rad_s) const {
  if (pieces_.empty()) throw InvalidArgument("empty segment chain");
  const std::size_t n = pieces_.size();
  SectionWaves wf, wb;
  const SectionProperties *of_f = nullptr, *of_b = nullptr;
  auto piece4 = [&](std::size_t i) {
    if (spin_rad_s == 0.0) {
      const TwoPort t = piece(i, f, 0.0, Whirl::Forward, wf, of_f);
      return two_plane(t, t);
    }
    return two_plane(piece(i, f, spin_rad_s, Whirl::Forward, wf, of_f), piece(i, f, spin_rad_s, Whirl::Backward, wb, of_b));
  };
  Block4 D;
  const TwoPort4 last = piece4(n - 1);
  Block4 g = ground_at(ground_[n], f, D) ? ground_end2_point(last, D) : last.b11;
  for (std::size_t k = n - 1; k-- > 0;) {
    if (ground_at(ground_[k + 1], f, D)) g = ground_point(g, D);
    g = couple_rigid_point(piece4(k), g);
  }
  if (ground_at(ground_[0], f, D)) g = ground_point(g, D);
  return g;
}

// ---- The assembly -------------------------------------------------------------------------------

AssemblyModel::AssemblyModel(const Assembly& assembly) : assembly_(assembly) {
  assembly_.check();
  const Assembly& a = assembly_;
  const int terms = a.modal_terms;
  auto with_model = [&](std::vector<Segment> segs) {
    for (auto& s : segs) s.shear_model = a.shear_model;
    return segs;
  };
  auto [tool_out, tool_in] = split_segments(a.tool.segments(a.shear_model), a.tool.overhang);
  tool_ = Chain(tool_out, a.method, terms);
  holder_ = Chain(insert_tool(with_model(a.holder), tool_in), a.method, terms);

  // Spindle: cut at every bearing position so bearings sit on nodes.
  std::vector<double> cuts;
  for (const Bearing& b : a.spindle.bearings) cuts.push_back(b.position);
  std::sort(cuts.begin(), cuts.end());
  std::vector<Segment> pieces, rest = with_model(a.spindle.segments);
  double done = 0.0;
  for (double c : cuts) {
    auto [outer, inner] = split_segments(rest, c - done);
    if (!outer.empty() && total_length(outer) > kLengthEps) {
      for (auto& s : outer) pieces.push_back(std::move(s));
      done = c;
    }
    rest = std::move(inner);
  }
  for (auto& s : rest) pieces.push_back(std::move(s));
  std::vector<double> node_pos{0.0};
  for (const auto& s : pieces) node_pos.push_back(node_pos.back() + s.length);
  spindle_ = Chain(std::move(pieces), a.method, terms);
  for (const Bearing& b : a.spindle.bearings) {
    const auto it = std::min_element(node_pos.begin(), node_pos.end(),
                                     [&](double x, double y) { return std::abs(x - b.position) < std::abs(y - b.position); });
    spindle_.add_ground(static_cast<std::size_t>(it - node_pos.begin()), b);
  }
}

std::vector<std::string> Assembly::warnings() const {
  std::vector<std::string> w;
  for (const Joint* j : {&spindle_holder, &holder_tool})
    if (!j->rigid) w.insert(w.end(), j->warnings.begin(), j->warnings.end());
  for (std::size_t i = 0; i < spindle.bearings.size(); ++i) {
    const Bearing& b = spindle.bearings[i];
    const std::string who = b.name.empty() ? fmt::format("spindle.bearing[{}]", i + 1) : b.name;
    if (!b.speed_table.empty())
      w.push_back(
          fmt::format("{}: its speed table is read at a stated speed (at_speed): by a prediction at that speed, and by "
                      "the zero-order lobes and plans at each of their speeds (LobesStudyOptions::speed_model); the "
                      "standstill single-plane model (and the time-domain lobes) uses its constant stiffness {:.4g} N/m and "
                      "damping {:.4g} N·s/m",
                      who, b.stiffness, b.damping));
    if (!b.isotropic())
      w.push_back(
          fmt::format("{}: its y values are read by the two-plane model (tool_point_two_plane: a prediction, and the "
                      "zero-order lobes and plans, which use it at each speed); the standstill single-plane model (and the "
                      "time-domain lobes) uses the x values in both directions",
                      who));
  }
  return w;
}

std::vector<std::string> AssemblyModel::warnings() const {
  std::vector<std::string> w = assembly_.warnings();
  for (const Chain* c : {&spindle_, &holder_, &tool_}) w.insert(w.end(), c->warnings().begin(), c->warnings().end());
  return w;
}

Block AssemblyModel::spindle_nose(double f) const { return spindle_.point(f); }
TwoPort AssemblyModel::holder(double f) const { return holder_.two_port(f); }
TwoPort AssemblyModel::tool(double f) const { return tool_.two_port(f); }

Block AssemblyModel::holder_tip(double f) const {
  return couple_point(holder_.two_port(f), spindle_.point(f), assembly_.spindle_holder, f);
}

Block AssemblyModel::tool_point(double f) const {
  return couple_point(tool_.two_port(f), holder_tip(f), assembly_.holder_tool, f);
}

bool AssemblyModel::isotropic() const {
  return std::all_of(assembly_.spindle.bearings.begin(), assembly_.spindle.bearings.end(),
                     [](const Bearing& b) { return b.isotropic(); });
}

double whirl_pole_window(double f, const std::vector<WhirlPole>& poles) {
  double w = 0.0;
  for (const WhirlPole& p : poles)
    if (std::abs(f - p.frequency_hz) <= p.window * p.frequency_hz) w = std::max(w, p.window);
  return w;
}

namespace {

// The whirl in which a spin's conical poles lie: ρI (1 − 2|Ω|/ω) (beam.hpp, conical_whirl_hz).
bool whirl_has_poles(double spin_rad_s, Whirl whirl) {
  return spin_rad_s != 0.0 && (whirl == Whirl::Forward) == (spin_rad_s > 0.0);
}

// WhirlPole::window from the direct coupling `at` (a block of the tool point) near the pole fc:
// the largest relative change over one-, two- and three-ulp steps at fc (1 + 1e-3) gives
// C = jitter d² (d = 1e-3), and the window sqrt(C / kWhirlPoleTolerance), capped.
template <class At>
double whirl_pole_window_of(double fc, At at) {
  constexpr double d = 1e-3;
  const double x = fc * (1.0 + d);
  const auto g = at(x);
  double jitter = 0.0, y = x;
  for (int k = 0; k < 3; ++k) {
    y = std::nextafter(y, 2.0 * x);
    jitter = std::max(jitter, (at(y) - g).norm() / g.norm());
  }
  return std::min(kWhirlPoleMaxWindow, std::sqrt(jitter * d * d / kWhirlPoleTolerance));
}

// The stencil about f for the window W (whirl_pole.hpp), else `at` at f.
template <class M, class At>
M whirl_pole_value(double f, double W, At at) {
  M value;
  if (detail::whirl_pole_stencil<M>(
          f, W,
          [&](const double* x, M* g) {
            for (int k = 0; k < 4; ++k) g[k] = at(x[k]);
            return true;
          },
          value))
    return value;
  return at(f);
}

}  // namespace

std::vector<WhirlPole> AssemblyModel::whirl_poles(double spin_rad_s, double f_lo, double f_hi) const {
  std::vector<WhirlPole> poles;
  if (spin_rad_s == 0.0) return poles;
  const Whirl whirl = spin_rad_s > 0.0 ? Whirl::Forward : Whirl::Backward;
  for (const Chain* c : {&spindle_, &holder_, &tool_})
    for (std::size_t i = 0; i < c->size(); ++i) {
      const SectionProperties& p = c->properties()[i];
      const double length = c->segments()[i].length, f0 = conical_whirl_estimate_hz(p, length, spin_rad_s);
      if (1.25 * f0 < f_lo || f0 > 1.25 * f_hi) continue;
      const double fc = conical_whirl_hz(p, length, spin_rad_s);
      if (!(fc > 0.0) || fc * (1.0 + kWhirlPoleMaxWindow) < f_lo || fc * (1.0 - kWhirlPoleMaxWindow) > f_hi) continue;
      // The window from the single-plane whirl (the bearings' x values, for anisotropic ones too:
      // the pole is the free piece's, its conditioning hardly the bearings'): one window per pole.
      poles.push_back({fc, whirl_pole_window_of(fc, [&](double x) { return whirl_tool_point_direct(x, spin_rad_s, whirl); })});
    }
  return poles;
}

Block AssemblyModel::whirl_tool_point_direct(double f, double spin_rad_s, Whirl whirl) const {
  const Block sh = couple_point(holder_.two_port(f, spin_rad_s, whirl), spindle_.point(f, spin_rad_s, whirl),
                                assembly_.spindle_holder, f);
  return couple_point(tool_.two_port(f, spin_rad_s, whirl), sh, assembly_.holder_tool, f);
}

Block AssemblyModel::tool_point(double f, double spin_rad_s, Whirl whirl) const {
  if (!isotropic())
    throw InvalidArgument(
        "AssemblyModel::tool_point for one whirl needs isotropic bearings (Bearing::stiffness_y, damping_y "
        "unset or equal to x)",
        "use tool_point_two_plane, which couples the planes");
  if (whirl_has_poles(spin_rad_s, whirl))
    if (const double W = whirl_pole_window(f, whirl_poles(spin_rad_s, f, f)); W > 0.0)
      return whirl_pole_value<Block>(f, W, [&](double x) { return whirl_tool_point_direct(x, spin_rad_s, whirl); });
  return whirl_tool_point_direct(f, spin_rad_s, whirl);
}

Block4 AssemblyModel::tool_point_two_plane(double f, double spin_rad_s) const {
  if (!isotropic())
    if (const double W = whirl_pole_window(f, whirl_poles(spin_rad_s, f, f)); W > 0.0)
      return whirl_pole_value<Block4>(f, W, [&](double x) { return tool_point_two_plane_direct(x, spin_rad_s); });
  return tool_point_two_plane_direct(f, spin_rad_s);
}

Block4 AssemblyModel::tool_point_two_plane_direct(double f, double spin_rad_s) const {
  if (isotropic()) {
    if (spin_rad_s == 0.0) return two_plane(tool_point(f));
    return two_plane(tool_point(f, spin_rad_s, Whirl::Forward), tool_point(f, spin_rad_s, Whirl::Backward));
  }
  // The holder and the tool are axisymmetric and free: their whirls combine per component.
  auto component = [&](const Chain& c) {
    if (spin_rad_s == 0.0) {
      const TwoPort t = c.two_port(f);
      return two_plane(t, t);
    }
    return two_plane(c.two_port(f, spin_rad_s, Whirl::Forward), c.two_port(f, spin_rad_s, Whirl::Backward));
  };
  const Block4 sh = couple_point(component(holder_), spindle_.point_two_plane(f, spin_rad_s), assembly_.spindle_holder, f);
  return couple_point(component(tool_), sh, assembly_.holder_tool, f);
}

TwoPort AssemblyModel::holder_tool(double f) const {
  return couple(tool_.two_port(f), holder_.two_port(f), assembly_.holder_tool, f);
}

AssemblyModel::Receptances AssemblyModel::evaluate(double f) const {
  Receptances r;
  r.S11 = spindle_.point(f);
  r.H = holder_.two_port(f);
  r.T = tool_.two_port(f);
  r.SH11 = couple_point(r.H, r.S11, assembly_.spindle_holder, f);
  r.SHT11 = couple_point(r.T, r.SH11, assembly_.holder_tool, f);
  return r;
}

namespace {

// Receptances between stations on `chain` at `distances` from its end 1, with the rest of the
// structure attached at its end 2 through `joint`, the rest known by its point receptance
// `rest11` there. Pieces between stations are chained by multi-point rigid junctions (no inverse
// of a free–free receptance); the rest enters as a ground of dynamic stiffness (K⁻¹ + rest11)⁻¹.
Eigen::MatrixXcd chain_stations(const Chain& chain, double f, const std::vector<double>& distances, const Block& rest11,
                                const Joint& joint, const char* what) {
  const double length = chain.length();
  std::vector<double> cuts;
  for (double d : distances) {
    if (!(d >= -kLengthEps && d <= length + kLengthEps))
      throw InvalidArgument(fmt::format("station at {} m from the {} lies outside [0, {}] m", d, what, length));
    cuts.push_back(std::clamp(d, 0.0, length));
  }
  std::vector<double> nodes{0.0};
  std::vector<double> sorted = cuts;
  std::sort(sorted.begin(), sorted.end());
  for (double c : sorted)
    if (c > nodes.back() + kLengthEps) nodes.push_back(c);
  if (length > nodes.back() + kLengthEps) nodes.push_back(length);
  const auto m = static_cast<Eigen::Index>(nodes.size());
  std::vector<Segment> rest = chain.segments();
  Eigen::MatrixXcd G;
  for (Eigen::Index k = 0; k + 1 < m; ++k) {
    auto [piece, inner] = split_segments(rest, nodes[k + 1] - nodes[k]);
    rest = std::move(inner);
    const Eigen::MatrixXcd P = as_matrix(Chain(piece, chain.method(), chain.modal_terms()).two_port(f));
    G = k == 0 ? P : join_rigid(G, k, P, 0);
  }
  Block Z;
  if (joint.rigid) {
    Z = inverse_checked(rest11, "point receptance of the structure beyond the stations");
  } else {
    const Block K = joint.parameters.stiffness(f);
    Z = K * inverse_checked(Block::Identity() + rest11 * K, "(I + B11 K) at the stations' joint");
  }
  G = ground_node(G, m - 1, Z);
  const auto n = static_cast<Eigen::Index>(cuts.size());
  Eigen::MatrixXcd out(2 * n, 2 * n);
  auto node_of = [&](double d) {
    return static_cast<Eigen::Index>(
        std::min_element(nodes.begin(), nodes.end(), [&](double x, double y) { return std::abs(x - d) < std::abs(y - d); }) -
        nodes.begin());
  };
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      out.block<2, 2>(2 * i, 2 * j) = G.block<2, 2>(2 * node_of(cuts[i]), 2 * node_of(cuts[j]));
  return out;
}

}  // namespace

Eigen::MatrixXcd AssemblyModel::tool_stations(double f, const std::vector<double>& distances) const {
  return chain_stations(tool_, f, distances, holder_tip(f), assembly_.holder_tool, "tool tip (the overhang)");
}

Eigen::MatrixXcd AssemblyModel::holder_stations(double f, const std::vector<double>& distances) const {
  return chain_stations(holder_, f, distances, spindle_nose(f), assembly_.spindle_holder, "holder tip (the holder)");
}

bool has_speed_tables(const Assembly& a) {
  return std::any_of(a.spindle.bearings.begin(), a.spindle.bearings.end(),
                     [](const Bearing& b) { return !b.speed_table.empty(); });
}

Assembly at_speed(const Assembly& assembly, double speed_rpm, bool extrapolate) {
  if (!(std::isfinite(speed_rpm) && speed_rpm >= 0.0))
    throw InvalidArgument(fmt::format("at_speed: speed {} rpm must be ≥ 0", speed_rpm));
  Assembly out = assembly;
  for (Bearing& b : out.spindle.bearings) {
    if (b.speed_table.empty()) continue;
    b.check();
    const std::vector<BearingSpeedPoint>& t = b.speed_table;
    const std::string who = b.name.empty() ? std::string("bearing") : b.name;
    if (t.size() == 1 || speed_rpm < t.front().speed_rpm || speed_rpm > t.back().speed_rpm) {
      const bool exact = t.size() == 1 && speed_rpm == t.front().speed_rpm;
      if (!exact && (!extrapolate || t.size() == 1))
        throw InvalidArgument(fmt::format("{}.speed_table covers {}–{} rpm; {} rpm lies outside it (extrapolation refused)", who,
                                          t.front().speed_rpm, t.back().speed_rpm, speed_rpm),
                              "extend the table to this speed, or allow extrapolation (at_speed's extrapolate: the end "
                              "rows' line extended)");
    }
    // The row pair around the speed (the end pair when extrapolating).
    std::size_t k = 1;
    while (k + 1 < t.size() && t[k].speed_rpm < speed_rpm) ++k;
    if (t.size() == 1) {
      b.stiffness = t[0].stiffness;
      b.damping = t[0].damping;
    } else {
      const BearingSpeedPoint &lo = t[k - 1], &hi = t[k];
      const double u = (speed_rpm - lo.speed_rpm) / (hi.speed_rpm - lo.speed_rpm);
      // Exact at the rows and for a flat table (lo = hi gives lo for any u).
      b.stiffness = lo.stiffness == hi.stiffness ? lo.stiffness : lo.stiffness + u * (hi.stiffness - lo.stiffness);
      b.damping = lo.damping == hi.damping ? lo.damping : lo.damping + u * (hi.damping - lo.damping);
    }
    if (b.stiffness < 0.0 || b.damping < 0.0)
      throw InvalidArgument(fmt::format("{}.speed_table extrapolated to {} rpm gives stiffness {} N/m, damping {} N·s/m: "
                                        "negative",
                                        who, speed_rpm, b.stiffness, b.damping),
                            "extend the table to this speed instead of extrapolating");
    b.speed_table.clear();
  }
  return out;
}

Assembly with_overhang(const Assembly& assembly, double overhang) {
  if (!std::isfinite(overhang) || !(overhang > 0.0)) throw InvalidArgument(fmt::format("overhang {} m must be > 0", overhang));
  Assembly a = assembly;
  const double inside = assembly.tool.length - assembly.tool.overhang;
  a.tool.overhang = overhang;
  a.tool.length = inside + overhang;
  a.check();
  return a;
}

BlockSeries couple_tool(const Assembly& assembly, const BlockSeries& sh11, const std::string& sh_name) {
  validate(sh11, sh_name, 1);
  const AssemblyModel model(assembly);
  BlockSeries out{sh11.frequency_hz, {}};
  out.blocks.reserve(sh11.size());
  for (std::size_t i = 0; i < sh11.size(); ++i) {
    const double f = sh11.frequency_hz[i];
    try {
      out.blocks.push_back(couple_point(model.tool(f), sh11.blocks[i], assembly.holder_tool, f));
    } catch (const NumericalError& e) {
      throw NumericalError(fmt::format("coupling the tool to {} at {} Hz: {}", sh_name, f, e.what()), e.hint());
    }
  }
  return out;
}

Block block_at(const std::function<Block(double)>& at, double frequency_hz) {
  try {
    return at(frequency_hz);
  } catch (const NumericalError& e) {
    throw NumericalError(fmt::format("at {} Hz: {}", frequency_hz, e.what()), e.hint());
  }
}

BlockSeries block_series(const std::vector<double>& frequency_hz, const std::function<Block(double)>& at) {
  BlockSeries s;
  s.frequency_hz = frequency_hz;
  s.blocks.reserve(frequency_hz.size());
  for (double f : frequency_hz) s.blocks.push_back(block_at(at, f));
  return s;
}

}  // namespace toolpoint
