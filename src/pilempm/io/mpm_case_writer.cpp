// Writing MPM case files: see mpm_case_writer.hpp. The keys and their order follow the reader
// (io/mpm_case.cpp, io/mpm_case_phase.cpp) and docs/mpm-case-files.md; a key the reader gives a
// default is left out where the case has that default, except in [solver], which is written
// whole (for its analysis) as the record of the settings used. One more key is one more line.
#include "pilempm/io/mpm_case_writer.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <string_view>
#include <utility>

#include "pilempm/constitutive/hypoplastic/hypoplastic_material.hpp"
#include "pilempm/constitutive/model_registry.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/core/number_text.hpp"
#include "pilempm/core/tensor.hpp"
#include "pilempm/io/output/atomic_file.hpp"

namespace pilempm {

using namespace simulation;

namespace {

constexpr double kKPa = 1.0e3;
constexpr double kInf = std::numeric_limits<double>::infinity();

// A double as a TOML float: the shortest text that reads back to it, with a decimal point or an
// exponent ("1.0", not the integer "1").
std::string float_text(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0.0 ? "inf" : "-inf";
  std::string text = fmt::format("{}", value);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return text;
}

// The shortest decimal x that the reader turns into `value` exactly through `read_back` (its unit
// conversion, e.g. x * 1e3 for kPa): `guess` (the value in the file's unit) with 1 to 17
// significant digits, then the doubles next to it. The nearest when none reads back exactly
// (a value computed in SI may have no decimal in the file's unit that gives it to the bit).
std::string exact_decimal(double value, double guess,
                          const std::function<double(double)>& read_back) {
  if (!std::isfinite(value) || !std::isfinite(guess)) return float_text(guess);
  for (int digits = 1; digits <= 17; ++digits) {
    const double x = with_significant_digits(guess, digits);
    if (read_back(x) == value) return float_text(x);
  }
  double up = guess, down = guess;
  for (int k = 0; k < 16; ++k) {
    up = std::nextafter(up, kInf);
    down = std::nextafter(down, -kInf);
    if (read_back(up) == value) return float_text(up);
    if (read_back(down) == value) return float_text(down);
  }
  return float_text(guess);
}

// A TOML basic string: the text in double quotes with '"', '\\' and control characters escaped.
std::string toml_string(std::string_view text) {
  std::string out = "\"";
  for (char ch : text) {
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(ch)));
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

// A key as TOML writes it: bare when it can be, else quoted.
std::string toml_key(std::string_view key) {
  const bool bare = !key.empty() && std::all_of(key.begin(), key.end(), [](char ch) {
    return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
           ch == '_' || ch == '-';
  });
  return bare ? std::string(key) : toml_string(key);
}

// TOML text written key by key: tables, arrays of tables, and inline tables for the groups of a
// model's parameters (it is the ParameterSink the models write their [[material]] keys to).
class TomlText final : public ParameterSink {
 public:
  void comment(std::string_view line) {
    out_ += line.empty() ? "#\n" : fmt::format("# {}\n", line);
  }
  void table(std::string_view header) { begin(fmt::format("[{}]", header)); }
  void array_table(std::string_view name) { begin(fmt::format("[[{}]]", name)); }

  /// `key = text`, the value already TOML.
  void value(std::string_view key, const std::string& text) {
    const std::string line = toml_key(key) + " = " + text;
    if (groups_.empty())
      out_ += line + '\n';
    else
      groups_.back().entries.push_back(line);
  }
  /// A number the reader converts with `read_back` (degrees to a friction coefficient, ...).
  void converted(std::string_view key, double si, double guess,
                 const std::function<double(double)>& read_back) {
    value(key, exact_decimal(si, guess, read_back));
  }

  void number(std::string_view key, double v) override { value(key, float_text(v)); }
  void scaled_number(std::string_view key, double si, double scale) override {
    converted(key, si, si / scale, [scale](double x) { return x * scale; });
  }
  void integer(std::string_view key, long v) override { value(key, fmt::format("{}", v)); }
  void text(std::string_view key, std::string_view v) override { value(key, toml_string(v)); }
  void boolean(std::string_view key, bool v) override { value(key, v ? "true" : "false"); }
  void begin_group(std::string_view key) override { groups_.push_back({std::string(key), {}}); }
  void end_group() override {
    Group group = std::move(groups_.back());
    groups_.pop_back();
    value(group.key,
          group.entries.empty() ? "{}" : fmt::format("{{ {} }}", fmt::join(group.entries, ", ")));
  }

  const std::string& str() const { return out_; }

 private:
  void begin(const std::string& header) {
    if (!out_.empty()) out_ += '\n';
    out_ += header + '\n';
  }
  struct Group {
    std::string key;
    std::vector<std::string> entries;
  };
  std::string out_;
  std::vector<Group> groups_;
};

[[noreturn]] void cannot_write(const MpmCase& c, const std::string& why) {
  throw Error(fmt::format("cannot write the MPM case {} as a case file: {}",
                          c.source.empty() ? std::string("(built in memory)") : c.source, why));
}

const char* side_name(mpm::Side side) {
  switch (side) {
    case mpm::Side::left:
      return "left";
    case mpm::Side::right:
      return "right";
    case mpm::Side::bottom:
      return "bottom";
    case mpm::Side::top:
      return "top";
  }
  return "top";
}

void write_axis(TomlText& t, const MpmCase& c, const char* name, const MpmGridAxis& axis,
                const std::vector<double>& nodes) {
  if (axis.nodes() != nodes)
    cannot_write(c, fmt::format("its {} nodes are not those of its grid axis {} (set the axis "
                                "the nodes come from)",
                                name, name));
  t.table(fmt::format("grid.{}", name));
  t.text("spacing", axis.graded ? "graded" : "uniform");
  t.number("min_m", axis.min);
  t.number("max_m", axis.max);
  if (!axis.graded) {
    t.integer("cells", axis.cells);
    return;
  }
  t.number("band_min_m", axis.band_min);
  t.number("band_max_m", axis.band_max);
  t.number("fine_spacing_m", axis.fine_spacing);
  t.number("growth_ratio", axis.growth_ratio);
  if (std::isfinite(axis.max_spacing)) t.number("max_spacing_m", axis.max_spacing);
}

void write_boundaries(TomlText& t, const MpmCase& c) {
  t.table("boundaries");
  for (mpm::Side side : {mpm::Side::left, mpm::Side::right, mpm::Side::bottom, mpm::Side::top}) {
    const mpm::BoundaryCondition condition = c.boundaries[static_cast<std::size_t>(side)];
    const auto absorbing =
        std::find_if(c.solver.absorbing_boundaries.begin(), c.solver.absorbing_boundaries.end(),
                     [&](const mpm::AbsorbingBoundary& b) { return b.side == side; });
    if (absorbing == c.solver.absorbing_boundaries.end()) {
      t.text(side_name(side), condition == mpm::BoundaryCondition::roller  ? "roller"
                              : condition == mpm::BoundaryCondition::fixed ? "fixed"
                                                                           : "free");
      continue;
    }
    if (condition != mpm::BoundaryCondition::free)
      cannot_write(c, fmt::format("its {} side is both absorbing and held", side_name(side)));
    t.begin_group(side_name(side));
    t.text("kind", "absorbing");
    t.number("density_kg_per_m3", absorbing->density);
    t.number("p_wave_speed_m_per_s", absorbing->p_wave_speed);
    t.number("s_wave_speed_m_per_s", absorbing->s_wave_speed);
    t.end_group();
  }
}

// [solver]: the analysis, the keys both analyses read, then the analysis's own keys (the reader
// refuses the other analysis's).
void write_solver(TomlText& t, const MpmCase& c) {
  const mpm::SolverSettings& s = c.solver;
  t.table("solver");
  t.text("analysis", to_string(c.analysis));
  t.text("shape_function", s.shape_function == mpm::ShapeFunction::linear  ? "linear"
                           : s.shape_function == mpm::ShapeFunction::ugimp ? "ugimp"
                                                                           : "cpgimp");
  t.number("gravity_m_per_s2", s.gravity);
  t.number("gravity_multiplier", s.gravity_multiplier);
  t.integer("threads", s.threads);
  t.boolean("volumetric_smoothing", s.volumetric_smoothing);  // B-bar in the quasi-static one
  if (c.analysis == MpmAnalysis::explicit_dynamic) {
    t.text("scheme", s.scheme == mpm::UpdateScheme::usl ? "usl" : "musl");
    t.number("flip_fraction", s.flip_fraction);
    t.integer("xpic_order", s.xpic_order);
    t.number("local_damping", s.local_damping);
    t.number("mass_scaling", s.mass_scaling);
    t.number("courant_number", s.courant_number);
    t.number("fixed_time_step_s", s.fixed_time_step);
    t.text("contact", s.contact == mpm::ContactScheme::surface ? "surface" : "nodes");
    return;
  }
  const mpm::quasi_static::Settings& q = c.quasi_static;
  if (c.displacement_step > 0.0) t.number("displacement_step_m", c.displacement_step);
  t.number("force_tolerance", q.force_tolerance);
  t.number("energy_tolerance", q.energy_tolerance);
  t.integer("max_iterations", q.max_iterations);
  t.integer("max_cuts", q.max_cuts);
  t.number("accept_tolerance", q.accept_tolerance);
  t.integer("accept_after_iterations", q.accept_after);
  t.integer("stall_iterations", q.stall_iterations);
  t.number("tangent_reuse", q.tangent_reuse);
  t.text("strain_increment", q.midpoint_strain ? "midpoint" : "start");
  // Only when not this build's default (a file that names a solver needs a build with it).
  if (q.linear_solver != mpm::quasi_static::Settings{}.linear_solver)
    t.text("linear_solver", mpm::quasi_static::to_string(q.linear_solver));
  t.number("contact_penalty_factor", q.contact.penalty_factor);
  t.number("newton_step_limit_cells", q.step_limit);
  t.number("contact_vertex_radius_cells", q.contact.vertex_radius);
  t.number("contact_smoothing", q.contact.smoothing);
  t.number("low_stress_stiffness", q.low_stress_stiffness);
  t.number("low_stress_pressure_Pa", q.low_stress_pressure);
  t.text("low_stress_use", q.low_stress_use == mpm::quasi_static::StabilisationUse::every_step
                               ? "every_step"
                               : "last_resort");
  if (q.inside_body_weakness > 0.0) t.number("inside_body_weakness", q.inside_body_weakness);
}

void write_integrator(TomlText& t, const IntegratorSettings& s) {
  const IntegratorSettings d{};
  if (s.scheme == d.scheme && s.tolerance == d.tolerance && s.fixed_substeps == d.fixed_substeps &&
      s.max_substeps == d.max_substeps && s.min_substep == d.min_substep &&
      s.min_mean_stress == d.min_mean_stress)
    return;  // the library's defaults
  t.table("integrator");
  t.text("scheme", to_string(s.scheme));
  t.number("tolerance", s.tolerance);
  t.number("min_mean_stress_Pa", s.min_mean_stress);
  t.integer("fixed_substeps", s.fixed_substeps);
  t.integer("max_substeps", s.max_substeps);
  t.number("min_substep", s.min_substep);
}

void write_material(TomlText& t, const MpmCase& c, const MaterialSpec& m) {
  const ModelRegistration& model = model_registry().at(m.model);
  if (!model.write)
    cannot_write(c, fmt::format("material \"{}\" is of model {}, which has no parameter writer",
                                m.name, m.model));
  t.array_table("material");
  t.text("name", m.name);
  t.text("model", m.model);
  if (!m.note.empty()) t.text("note", m.note);
  model.write(*m.parameters, t);
}

// The [[material]] tables: the case's own, then a region's material that is not a built-in set
// and not among them.
void write_materials(TomlText& t, const MpmCase& c) {
  std::vector<std::string> written;
  for (const MaterialSpec& m : c.materials) {
    write_material(t, c, m);
    written.push_back(m.name);
  }
  for (const MpmRegion& r : c.regions)
    if (!r.material.builtin &&
        std::find(written.begin(), written.end(), r.material.name) == written.end()) {
      write_material(t, c, r.material);
      written.push_back(r.material.name);
    }
}

void write_region(TomlText& t, const MpmRegion& r) {
  const mpm::RectangleFill& f = r.fill;
  const bool hypoplastic = r.material.is_hypoplastic();
  t.array_table("region");
  t.text("name", r.name);
  t.number("x_min_m", f.x_min);
  t.number("x_max_m", f.x_max);
  t.number("y_min_m", f.y_min);
  t.number("y_max_m", f.y_max);
  if (f.particles_per_cell_x == f.particles_per_cell_y)
    t.integer("particles_per_cell", f.particles_per_cell_x);
  else
    t.value("particles_per_cell",
            fmt::format("[{}, {}]", f.particles_per_cell_x, f.particles_per_cell_y));
  t.number("density_kg_per_m3", f.density);
  if (f.initial_velocity.x() != 0.0) t.number("velocity_x_m_per_s", f.initial_velocity.x());
  if (f.initial_velocity.y() != 0.0) t.number("velocity_y_m_per_s", f.initial_velocity.y());
  t.text("material", r.material.name);
  if (hypoplastic && r.igs_in_region && r.igs) write_igs(*r.igs, "igs", t);
  if (hypoplastic && !r.igs_compression) t.text("igs_initial", "zero");
  const bool geostatic = r.initial_stress == MpmInitialStress::geostatic;
  t.text("initial_stress", geostatic ? "geostatic" : "zero");
  if (geostatic) t.number("K0", r.K0);
  if (hypoplastic || r.e0 != 0.0) t.number("e0", r.e0);
  if (hypoplastic || r.e0_at != VoidRatioConvention::at_initial_stress)
    t.text("e0_at", to_string(r.e0_at));
}

void write_body(TomlText& t, const MpmBody& b) {
  const auto degrees_to_radians = [](double deg) { return deg * kPi / 180.0; };
  t.array_table("body");
  t.text("name", b.name);
  if (b.kind == MpmBodyKind::pile) {
    t.text("kind", "pile");
    t.number("radius_m", b.radius);
    t.number("tip_y_m", b.tip_y);
    const bool flat = b.apex_angle == kPi;
    t.text("tip", flat ? "flat" : "conical");
    if (!flat)
      t.converted("apex_angle_deg", b.apex_angle, b.apex_angle * 180.0 / kPi, degrees_to_radians);
  } else {
    t.text("kind", "polygon");
    std::vector<std::string> points;
    for (const mpm::Vec2& v : b.vertices)
      points.push_back(fmt::format("[{}, {}]", float_text(v.x()), float_text(v.y())));
    t.value("vertices_m", fmt::format("[{}]", fmt::join(points, ", ")));
  }
  t.converted("interface_friction_angle_deg", b.friction, std::atan(b.friction) * 180.0 / kPi,
              [](double deg) { return std::tan(deg * kPi / 180.0); });
  if (b.contact_distance > 0.0) t.number("contact_distance_m", b.contact_distance);
}

void write_traction(TomlText& t, const MpmCase& c, const MpmTraction& tr) {
  const std::string& region = c.regions.at(static_cast<std::size_t>(tr.region)).name;
  if (std::count_if(c.regions.begin(), c.regions.end(),
                    [&](const MpmRegion& r) { return r.name == region; }) != 1)
    cannot_write(c, fmt::format("a traction acts on region \"{}\", and several regions have "
                                "that name",
                                region));
  const auto from_kPa = [](double x) { return x * kKPa; };
  t.array_table("traction");
  t.text("region", region);
  t.text("side", side_name(tr.side));
  t.converted("normal_kPa", tr.normal, tr.normal / kKPa, from_kPa);
  if (tr.shear != 0.0) t.converted("shear_kPa", tr.shear, tr.shear / kKPa, from_kPa);
}

// The case-file key of a stop rule, e.g. "stop_force_y_below_N".
std::string stop_key(const MpmStopRule& rule) {
  const char axis = rule.component == 0 ? 'x' : 'y';
  switch (rule.quantity) {
    case MpmStopQuantity::displacement:
      return fmt::format("stop_displacement_{}_m", axis);
    case MpmStopQuantity::phase_displacement:
      return fmt::format("stop_phase_displacement_{}_m", axis);
    case MpmStopQuantity::force_below:
      return fmt::format("stop_force_{}_below_N", axis);
    case MpmStopQuantity::force_above:
      return fmt::format("stop_force_{}_above_N", axis);
  }
  return rule.key;
}

void write_phase(TomlText& t, const MpmCase& c, const MpmPhase& p) {
  t.array_table("phase");
  t.text("name", p.name);
  if (p.kind == MpmPhaseKind::geostatic) t.text("kind", "geostatic");
  if (p.role != MpmPhaseRole::none) t.text("role", to_string(p.role));
  t.number("duration_s", p.duration);
  if (p.gravity_multiplier != c.solver.gravity_multiplier)
    t.number("gravity_multiplier", p.gravity_multiplier);
  if (c.analysis == MpmAnalysis::quasi_static) {
    if (p.displacement_step > 0.0) t.number("displacement_step_m", p.displacement_step);
  } else if (p.local_damping != c.solver.local_damping) {
    t.number("local_damping", p.local_damping);
  }
  if (p.output_interval != p.duration) t.number("output_interval_s", p.output_interval);
  if (p.energy_interval != p.output_interval / 10.0)
    t.number("energy_interval_s", p.energy_interval);
  if (p.traction_multiplier != 1.0) t.number("traction_multiplier", p.traction_multiplier);
  if (!p.checkpoint) t.boolean("checkpoint", false);

  std::vector<std::string> keys;
  bool force_rule = false;
  for (const MpmStopRule& rule : p.stop_rules) {
    const std::string key = stop_key(rule);
    if (std::find(keys.begin(), keys.end(), key) != keys.end())
      cannot_write(c, fmt::format("phase \"{}\" has two rules {}", p.name, key));
    keys.push_back(key);
    t.number(key, rule.value);
    force_rule = force_rule || rule.quantity == MpmStopQuantity::force_below ||
                 rule.quantity == MpmStopQuantity::force_above;
  }
  if (force_rule && p.stop_force_averaging != 0.0)
    t.number("stop_force_averaging_s", p.stop_force_averaging);
  if (!p.stop_rules.empty())
    t.text("stop_body", c.bodies.at(static_cast<std::size_t>(p.stop_body)).name);

  for (std::size_t b = 0; b < p.body_motion.size() && b < c.bodies.size(); ++b) {
    const MpmBodyMotion& m = p.body_motion[b];
    if (m.velocity.x() == 0.0 && m.velocity.y() == 0.0 && m.ramp == 0.0) continue;  // at rest
    t.table("phase.body." + toml_key(c.bodies[b].name));
    if (m.velocity.x() != 0.0) t.number("velocity_x_m_per_s", m.velocity.x());
    if (m.velocity.y() != 0.0) t.number("velocity_y_m_per_s", m.velocity.y());
    if (m.ramp != 0.0) t.number("ramp_s", m.ramp);
  }

  // [phase.materials]: "the regions' material" = "the new set", once per material.
  std::vector<std::pair<std::string, std::string>> changes;
  for (const MpmMaterialChange& change : p.material_changes) {
    const std::string& role = c.regions.at(static_cast<std::size_t>(change.model)).material.name;
    const auto same = std::find_if(changes.begin(), changes.end(),
                                   [&](const auto& entry) { return entry.first == role; });
    if (same == changes.end())
      changes.emplace_back(role, change.material);
    else if (same->second != change.material)
      cannot_write(c, fmt::format("phase \"{}\" changes the regions of material \"{}\" to two "
                                  "different sets",
                                  p.name, role));
  }
  if (changes.empty()) return;
  t.table("phase.materials");
  for (const auto& [role, material] : changes) t.text(role, material);
}

}  // namespace

std::string mpm_case_text(const MpmCase& c, const std::vector<std::string>& comments) {
  TomlText t;
  for (const std::string& line : comments) t.comment(line);
  if (!c.title.empty()) t.text("title", c.title);
  t.table("geometry");
  t.text("kind", c.geometry == mpm::Geometry::axisymmetric ? "axisymmetric" : "plane-strain");
  write_axis(t, c, "x", c.x_axis, c.x_nodes);
  write_axis(t, c, "y", c.y_axis, c.y_nodes);
  write_boundaries(t, c);
  write_solver(t, c);
  write_integrator(t, c.integrator);
  write_materials(t, c);
  for (const MpmRegion& r : c.regions) write_region(t, r);
  for (const MpmBody& b : c.bodies) write_body(t, b);
  for (const MpmTraction& tr : c.tractions) write_traction(t, c, tr);
  for (const MpmPhase& p : c.phases) write_phase(t, c, p);
  return t.str();
}

void write_mpm_case(const std::filesystem::path& file, const MpmCase& c,
                    const std::vector<std::string>& comments) {
  write_file_atomically(file, mpm_case_text(c, comments));
}

}  // namespace pilempm
