// Output of MPM runs: see mpm_output.hpp.
#include "pilempm/io/mpm_output.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <memory>
#include <sstream>
#include <string_view>

#include "pilempm/constitutive/hypoplastic/hypoplastic.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/core/tensor.hpp"
#include "pilempm/io/mpm_checkpoint.hpp"
#include "pilempm/io/output/atomic_file.hpp"
#include "pilempm/io/output/format.hpp"
#include "pilempm/simulation/body_force_means.hpp"
#include "pilempm/simulation/explicit_scheme.hpp"
#include "pilempm/simulation/phase_control.hpp"
#include "pilempm/simulation/progress.hpp"
#include "pilempm/simulation/quasi_static_scheme.hpp"

namespace pilempm {

using namespace simulation;

namespace {

constexpr double kKPa = 1.0e3;

// The part of a polygon where n . x <= limit (Sutherland and Hodgman's clipping against one
// half-plane; a convex polygon stays convex and keeps its orientation).
std::vector<mpm::Vec2> clipped(const std::vector<mpm::Vec2>& polygon, const mpm::Vec2& normal,
                               double limit) {
  std::vector<mpm::Vec2> out;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const mpm::Vec2& a = polygon[k];
    const mpm::Vec2& b = polygon[(k + 1) % polygon.size()];
    const double da = normal.dot(a) - limit, db = normal.dot(b) - limit;
    if (da <= 0.0) out.push_back(a);
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0))
      out.push_back(a + (da / (da - db)) * (b - a));
  }
  return out;
}

}  // namespace

std::vector<mpm::Vec2> mpm_body_outline(const mpm::RigidBody& body, double top, bool half_section) {
  std::vector<mpm::Vec2> outline = clipped(body.vertices(), mpm::Vec2(0.0, 1.0), top);
  if (half_section) outline = clipped(outline, mpm::Vec2(-1.0, 0.0), 0.0);
  return outline.size() >= 3 ? outline : std::vector<mpm::Vec2>{};
}

PolygonMesh mpm_body_mesh(const mpm::MpmState& solver) {
  PolygonMesh mesh;
  PointField body_index{"body", 1, {}};
  const double top = solver.grid().y_axis().end();
  for (int b = 0; b < solver.rigid_body_count(); ++b) {
    const std::vector<mpm::Vec2> outline = mpm_body_outline(solver.rigid_body(b), top);
    if (outline.empty()) continue;  // wholly above the grid
    for (const mpm::Vec2& v : outline) {
      mesh.connectivity.push_back(static_cast<std::int64_t>(mesh.coordinates.size() / 3));
      mesh.coordinates.insert(mesh.coordinates.end(), {v.x(), v.y(), 0.0});
    }
    mesh.offsets.push_back(static_cast<std::int64_t>(mesh.connectivity.size()));
    body_index.values.push_back(b);
  }
  mesh.cell_fields.push_back(std::move(body_index));
  return mesh;
}

std::vector<double> mpm_igs_sizes(const mpm::MpmState& solver) {
  std::vector<double> sizes;
  for (const ModelPtr& model : solver.materials()) {
    const auto* hypoplastic = dynamic_cast<const Hypoplastic*>(model.get());
    sizes.push_back(hypoplastic != nullptr && hypoplastic->intergranular().enabled()
                        ? hypoplastic->intergranular().R
                        : 0.0);
  }
  return sizes;
}

PointCloud mpm_particle_cloud(const mpm::MpmState& solver,
                              const std::vector<mpm::Vec2>& initial_position,
                              const std::vector<int>& material_index) {
  const mpm::Particles& particles = solver.particles();
  const std::size_t n = particles.size();
  // The models' own output fields by name (e.g. igs_rho), 0 where a particle's model lacks one;
  // own[m][k]: model m's index of field k, -1 if it has none.
  const std::vector<ModelPtr>& models = solver.materials();
  std::vector<PointField> model_fields;
  std::vector<std::vector<int>> own(models.size());
  for (std::size_t m = 0; m < models.size(); ++m) {
    const std::vector<std::string> names = models[m]->output_fields();
    for (std::size_t j = 0; j < names.size(); ++j) {
      auto it = std::find_if(model_fields.begin(), model_fields.end(),
                             [&](const PointField& f) { return f.name == names[j]; });
      if (it == model_fields.end()) {
        model_fields.push_back({names[j], 1, std::vector<double>(n)});
        it = model_fields.end() - 1;
      }
      const std::size_t k = static_cast<std::size_t>(it - model_fields.begin());
      if (own[m].size() <= k) own[m].resize(k + 1, -1);
      own[m][k] = static_cast<int>(j);
    }
  }

  PointCloud cloud;
  cloud.coordinates.resize(3 * n);
  PointField stress{"stress_kPa_compression_positive", 9, std::vector<double>(9 * n)};
  PointField mean{"p_kPa", 1, std::vector<double>(n)};
  PointField deviator{"q_kPa", 1, std::vector<double>(n)};
  PointField void_ratio{"void_ratio", 1, std::vector<double>(n)};
  PointField velocity{"velocity_m_per_s", 3, std::vector<double>(3 * n)};
  PointField displacement{"displacement_m", 3, std::vector<double>(3 * n)};
  PointField material{"material", 1, std::vector<double>(n)};
  for (std::size_t p = 0; p < n; ++p) {
    const mpm::Vec2& x = particles.position[p];
    cloud.coordinates[3 * p] = x.x();
    cloud.coordinates[3 * p + 1] = x.y();
    const MaterialState& state = particles.state[p];
    const Vec6& s = state.stress;
    const double xy = s[k12] / kSqrt2, yz = s[k23] / kSqrt2, xz = s[k13] / kSqrt2;
    const double full[9] = {s[k11], xy, xz, xy, s[k22], yz, xz, yz, s[k33]};
    for (int k = 0; k < 9; ++k) stress.values[9 * p + k] = -full[k] / kKPa;
    mean.values[p] = mean_stress(s) / kKPa;
    deviator.values[p] = deviator_stress(s) / kKPa;
    void_ratio.values[p] = state.void_ratio;
    const int model = particles.material[p];
    const std::vector<int>& fields = own[static_cast<std::size_t>(model)];
    for (std::size_t k = 0; k < fields.size(); ++k)
      if (fields[k] >= 0)
        model_fields[k].values[p] = models[static_cast<std::size_t>(model)]->output_field(
            static_cast<std::size_t>(fields[k]), state);
    velocity.values[3 * p] = particles.velocity[p].x();
    velocity.values[3 * p + 1] = particles.velocity[p].y();
    const mpm::Vec2 u = x - initial_position[p];
    displacement.values[3 * p] = u.x();
    displacement.values[3 * p + 1] = u.y();
    material.values[p] = material_index[static_cast<std::size_t>(model)];
  }
  cloud.fields.push_back(std::move(stress));
  cloud.fields.push_back(std::move(mean));
  cloud.fields.push_back(std::move(deviator));
  cloud.fields.push_back(std::move(void_ratio));
  for (PointField& field : model_fields) cloud.fields.push_back(std::move(field));
  cloud.fields.push_back(std::move(velocity));
  cloud.fields.push_back(std::move(displacement));
  cloud.fields.push_back(std::move(material));
  return cloud;
}

std::string mpm_energies_header(mpm::Geometry geometry) {
  const char* per = geometry == mpm::Geometry::axisymmetric
                        ? "per radian (axisymmetric)"
                        : "per metre of thickness (plane strain)";
  return fmt::format(
      "# energies in J {}; kinetic at the end of the step, the others accumulated since t = 0; "
      "kinetic + internal + damping + absorbed - external_work - contact_work stays constant "
      "(contact_work: work of the rigid bodies on the soil; absorbed: by absorbing boundaries)\n"
      "time_s,step,dt_s,kinetic_J,internal_J,external_work_J,damping_J,contact_work_J,"
      "absorbed_J\n",
      per);
}

std::string mpm_energies_row(const mpm::MpmState& solver, double time_step) {
  const mpm::Energies& e = solver.energies();
  return csv_row({csv_number(solver.time(), 10), std::to_string(solver.steps()),
                  csv_number(time_step, 6), csv_number(e.kinetic, 10), csv_number(e.internal, 10),
                  csv_number(e.external_work, 10), csv_number(e.damping, 10),
                  csv_number(e.contact_work, 10), csv_number(e.absorbed, 10)});
}

std::string mpm_load_steps_header() {
  return "# quasi-static load steps: the Newton work of each, at the pseudo-time of its end; "
         "solves: 1, or more where a force stop rule was bisected within the step (the columns "
         "sum over them); accepted: sub-increments accepted above the force tolerance "
         "(accept_tolerance) and the largest ||R|| / F_ref of them; stabilised: sub-increments "
         "that kept the low-stress stabilisation's stress (low_stress_stiffness) and the largest "
         "share of it they kept; rescued: the step's solves whose cuts without the stabilisation "
         "ran out and that were finished with it (low_stress_use = \"last_resort\"); penetration: "
         "the "
         "largest of a contact point into a body at the "
         "step's end\n"
         "time_s,step,phase,solves,iterations,cuts,accepted,largest_accepted_residual,stabilised,"
         "stabilisation_share,rescued,unknowns,penetration_m,material_s,assembly_s,factorisation_s,"
         "wall_"
         "s\n";
}

std::string mpm_load_steps_row(const mpm::MpmState& solver, const std::string& phase,
                               const simulation::LoadStepRecord& record, double penetration) {
  return csv_row({csv_number(solver.time(), 10), std::to_string(solver.steps()), phase,
                  std::to_string(record.solves), std::to_string(record.iterations),
                  std::to_string(record.cuts), std::to_string(record.accepted),
                  csv_number(record.largest_accepted_residual, 3),
                  std::to_string(record.stabilised),
                  csv_number(record.largest_stabilisation_share, 3), std::to_string(record.rescued),
                  std::to_string(record.unknowns), csv_number(penetration, 4),
                  csv_number(record.material_seconds, 4), csv_number(record.assembly_seconds, 4),
                  csv_number(record.factorisation_seconds, 4), csv_number(record.wall_seconds, 4)});
}

namespace {

// The surface part names of all bodies, in order of first appearance.
std::vector<std::string> all_part_names(const mpm::MpmState& solver) {
  std::vector<std::string> names;
  for (int b = 0; b < solver.rigid_body_count(); ++b)
    for (const std::string& name : solver.rigid_body(b).part_names())
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  return names;
}

// A part name as part of a column name: letters, digits and '_' ("edge 0" -> "edge_0").
std::string column_word(const std::string& name) {
  std::string word = name;
  for (char& ch : word)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return word;
}

}  // namespace

std::string mpm_bodies_header(const mpm::MpmState& solver) {
  const bool axisymmetric = solver.geometry() == mpm::Geometry::axisymmetric;
  const bool inertial = std::string_view(solver.analysis()) == "explicit";
  std::string header = fmt::format(
      "# rigid bodies: displacement since t = 0, velocity, contact force of the soil on the body "
      "({}) in {} (+y up: a body pushed down into soil gets force_y > 0), in total and per "
      "surface part\n",
      inertial ? "the mean over the time since the previous row of the body"
               : "at the row's time, in equilibrium (quasi-static; time is pseudo-time)",
      axisymmetric ? "N of the full body (2 pi times the per-radian force; force_x = 0, the "
                     "radial forces cancel around the axis)"
                   : "N per metre of thickness (plane strain)");
  header +=
      "time_s,step,phase,body,displacement_x_m,displacement_y_m,velocity_x_m_per_s,"
      "velocity_y_m_per_s,force_x_N,force_y_N";
  for (const std::string& part : all_part_names(solver)) {
    header += ",force_y_";
    header += column_word(part);
    header += "_N";
  }
  header += '\n';
  return header;
}

std::string mpm_bodies_rows(const mpm::MpmState& solver, const std::vector<std::string>& body_names,
                            const std::string& phase,
                            const std::vector<mpm::RigidBodyForce>* forces) {
  const mpm::Geometry geometry = solver.geometry();
  const double factor = mpm_full_body_factor(geometry);
  const double radial = geometry == mpm::Geometry::axisymmetric ? 0.0 : 1.0;
  const std::vector<std::string> parts = all_part_names(solver);
  std::string rows;
  for (int b = 0; b < solver.rigid_body_count(); ++b) {
    const mpm::RigidBody& body = solver.rigid_body(b);
    const mpm::RigidBodyForce& force =
        forces != nullptr ? forces->at(static_cast<std::size_t>(b)) : solver.rigid_body_force(b);
    rows += fmt::format(
        "{},{},{},{},{},{},{},{},{},{}", csv_number(solver.time(), 10), solver.steps(),
        csv_field(phase), csv_field(body_names.at(static_cast<std::size_t>(b))),
        csv_number(body.displacement().x(), 10), csv_number(body.displacement().y(), 10),
        csv_number(body.velocity().x(), 10), csv_number(body.velocity().y(), 10),
        csv_number(radial * factor * force.total.x(), 10),
        csv_number(factor * force.total.y(), 10));
    const std::vector<std::string>& own = body.part_names();
    for (const std::string& part : parts) {
      rows += ',';
      const auto at = std::find(own.begin(), own.end(), part);
      if (at == own.end()) continue;
      const auto index = static_cast<std::size_t>(at - own.begin());
      if (index < force.parts.size()) rows += csv_number(factor * force.parts[index].y(), 10);
    }
    rows += '\n';
  }
  return rows;
}

std::string mpm_checkpoint_name(std::size_t phases_done, const std::string& phase) {
  std::string name = phase;
  for (char& ch : name)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_' && ch != '.')
      ch = '_';
  return fmt::format("checkpoint_{:02d}_{}.h5", phases_done, name);
}

namespace {

// The records of a checkpoint: the output text so far and the snapshot series.
constexpr const char* kEnergiesRecord = "energies.csv";
constexpr const char* kBodiesRecord = "bodies.csv";
constexpr const char* kLoadStepsRecord = "load_steps.csv";
// "time<TAB>file relative to the folder[<TAB>part]" (no part: 0, the particles; 1: the bodies)
constexpr const char* kSeriesRecord = "particles.pvd";

// The files of a run, written as the loop reaches their times: the VTU snapshots and their
// series, energies.csv and bodies.csv (rewritten at every snapshot and at the end), checkpoints.
class MpmOutputWriter final : public RunObserver {
 public:
  // `scheme`: the run's analysis, whose next step each row of energies.csv gives (and, when it
  // is the quasi-static one, whose load steps load_steps.csv lists).
  MpmOutputWriter(const MpmCase& c, const std::filesystem::path& out_dir, Scheme& scheme,
                  MpmRunSummary& summary)
      : case_(c),
        scheme_(scheme),
        quasi_static_(dynamic_cast<const QuasiStaticScheme*>(&scheme)),
        out_dir_(out_dir),
        absolute_out_(std::filesystem::absolute(out_dir)),
        summary_(summary),
        series_(absolute_out_ / "particles.pvd"),
        initial_position_(scheme.state().particles().position),
        with_bodies_(!c.bodies.empty()),
        energies_(mpm_energies_header(c.geometry)),
        bodies_(with_bodies_ ? mpm_bodies_header(scheme.state()) : std::string()),
        load_steps_(quasi_static_ != nullptr ? mpm_load_steps_header() : std::string()) {
    std::map<std::string, int> distinct;
    for (const std::string& name : c.material_names)
      material_index_.push_back(
          distinct.emplace(name, static_cast<int>(distinct.size())).first->second);
    for (const MpmBody& b : c.bodies) body_names_.push_back(b.name);
    summary_.pvd_file = out_dir / "particles.pvd";
    summary_.energies_file = out_dir / "energies.csv";
    if (with_bodies_) summary_.bodies_file = out_dir / "bodies.csv";
    if (quasi_static_ != nullptr) summary_.load_steps_file = out_dir / "load_steps.csv";
  }

  // The output of the run that wrote `restart` so far: its records, its initial positions.
  void restore(const MpmCheckpointInfo& info, const std::filesystem::path& restart) {
    if (info.initial_position.size() == initial_position_.size())
      initial_position_ = info.initial_position;
    auto record = [&](const char* name) {
      const auto at = info.records.find(name);
      return at == info.records.end() ? std::string() : at->second;
    };
    if (!record(kEnergiesRecord).empty()) energies_ = record(kEnergiesRecord);
    if (with_bodies_ && !record(kBodiesRecord).empty()) bodies_ = record(kBodiesRecord);
    if (quasi_static_ != nullptr && !record(kLoadStepsRecord).empty())
      load_steps_ = record(kLoadStepsRecord);
    const std::filesystem::path from = std::filesystem::absolute(restart).parent_path();
    std::istringstream entries(record(kSeriesRecord));
    std::string line;
    while (std::getline(entries, line)) {
      const auto tab = line.find('\t');
      if (tab == std::string::npos) continue;
      const double time = std::stod(line.substr(0, tab));
      const auto part_tab = line.find('\t', tab + 1);
      const int part = part_tab == std::string::npos ? 0 : std::stoi(line.substr(part_tab + 1));
      const std::filesystem::path file =
          (from / line.substr(tab + 1, part_tab == std::string::npos ? std::string::npos
                                                                     : part_tab - tab - 1))
              .lexically_normal();
      series_.add(time, file, part);
      series_entries_.push_back({time, file, part});
      if (part == 0) ++vtu_count_;
    }
  }

  void run_start(const Scheme& /*scheme*/, std::size_t first_phase) override {
    if (first_phase == 0) return;
    // The checkpoint's records end with the rows and the snapshot of this time.
    series_.write();
    write_records();
  }

  void after_step(const Scheme& scheme, const MpmPhase& phase, double dt) override {
    if (with_bodies_ && scheme.inertial()) force_means_.add_step(scheme.state(), dt);
    if (quasi_static_ != nullptr)
      load_steps_ += mpm_load_steps_row(scheme.state(), phase.name, quasi_static_->last_advance(),
                                        quasi_static_->solver().max_penetration());
  }

  void record(const Scheme& scheme, const MpmPhase& phase) override {
    const mpm::MpmState& solver = scheme.state();
    energies_ += mpm_energies_row(solver, scheme_.step_length());
    if (with_bodies_) {
      const std::vector<mpm::RigidBodyForce> means = force_means_.take(solver);
      bodies_ += mpm_bodies_rows(solver, body_names_, phase.name, &means);
    }
  }

  void snapshot(const Scheme& scheme, const MpmPhase& /*phase*/) override {
    const mpm::MpmState& solver = scheme.state();
    const std::string name = fmt::format("particles_{:05d}.vtu", vtu_count_++);
    const std::filesystem::path file = out_dir_ / name;
    write_vtu(file, mpm_particle_cloud(solver, initial_position_, material_index_));
    series_.add(solver.time(), absolute_out_ / name);
    series_entries_.push_back({solver.time(), absolute_out_ / name, 0});
    if (with_bodies_) {
      // The bodies beside the particles: part 1 of the series' multiblock data set.
      const std::string bodies = fmt::format("bodies_{:05d}.vtu", vtu_count_ - 1);
      write_vtu(out_dir_ / bodies, mpm_body_mesh(solver));
      series_.add(solver.time(), absolute_out_ / bodies, 1);
      series_entries_.push_back({solver.time(), absolute_out_ / bodies, 1});
    }
    series_.write();
    write_records();
    summary_.vtu_files.push_back(file);
  }

  void checkpoint(const Scheme& scheme, std::size_t phases_done, const MpmPhase& phase) override {
    write_checkpoint(scheme, phases_done, phase, "");
  }

  void failed(const Scheme& scheme, const MpmPhase& phase) override {
    write_records();
    if (scheme.inertial()) return;  // an explicit step that failed leaves a state half done
    // The quasi-static state is that of the last converged load step: kept as a checkpoint
    // from which the failed phase can be run again (e.g. with a smaller displacement step).
    const auto index = static_cast<std::size_t>(&phase - case_.phases.data());
    try {
      write_checkpoint(scheme, index, phase, "last_converged_");
    } catch (const Error&) {
      // The run's own error is the one to report.
    }
  }
  void run_end(const Scheme& /*scheme*/) override { write_records(); }

 private:
  // A checkpoint after `phases_done` phases; `prefix` before its usual name.
  void write_checkpoint(const Scheme& scheme, std::size_t phases_done, const MpmPhase& phase,
                        const std::string& prefix) {
    MpmCheckpointInfo info;
    info.case_source = case_.source;
    info.next_phase = static_cast<int>(phases_done);
    info.phase_start = scheme.time();
    info.initial_position = initial_position_;
    info.records[kEnergiesRecord] = energies_;
    if (with_bodies_) info.records[kBodiesRecord] = bodies_;
    if (quasi_static_ != nullptr) info.records[kLoadStepsRecord] = load_steps_;
    std::string entries;
    for (const SeriesEntry& e : series_entries_) {
      entries += fmt::format("{:.17g}\t", e.time);
      entries += e.file.lexically_relative(absolute_out_).generic_string();
      entries += e.part == 0 ? std::string("\n") : fmt::format("\t{}\n", e.part);
    }
    info.records[kSeriesRecord] = entries;
    for (const CheckpointedState* state : checkpointed_) {
      const std::string name = state->record_name();
      if (info.records.count(name) != 0)
        throw Error(fmt::format("checkpoint record \"{}\" named twice", name));
      info.records[name] = state->save(phases_done, prefix.empty());
    }
    const std::filesystem::path file =
        out_dir_ / (prefix + mpm_checkpoint_name(phases_done, phase.name));
    write_mpm_checkpoint(file, scheme.state(), info);
    summary_.checkpoints.push_back(file);
  }

  void write_records() {
    write_file_atomically(summary_.energies_file, energies_);
    if (with_bodies_) write_file_atomically(summary_.bodies_file, bodies_);
    if (quasi_static_ != nullptr) write_file_atomically(summary_.load_steps_file, load_steps_);
  }

  const MpmCase& case_;
  Scheme& scheme_;
  const QuasiStaticScheme* quasi_static_;
  std::filesystem::path out_dir_, absolute_out_;
  MpmRunSummary& summary_;
  PvdSeries series_;
  struct SeriesEntry {
    double time;
    std::filesystem::path file;
    int part;
  };
  std::vector<SeriesEntry> series_entries_;  // for checkpoints
  std::vector<mpm::Vec2> initial_position_;
  std::vector<int> material_index_;
  std::vector<std::string> body_names_;
  bool with_bodies_;
  std::string energies_, bodies_, load_steps_;
  std::size_t vtu_count_ = 0;
  MpmBodyForceMeans force_means_;

 public:
  // The caller's state kept in each checkpoint (MpmRunHooks::checkpointed).
  std::vector<CheckpointedState*> checkpointed_;
};

}  // namespace

MpmRunSummary run_mpm_case(const MpmCase& c, const std::filesystem::path& out_dir,
                           std::ostream* progress_stream, const std::filesystem::path& restart,
                           const MpmRunHooks& hooks) {
  prepare_output_directory(out_dir);
  std::unique_ptr<Scheme> scheme;
  QuasiStaticScheme* quasi_static = nullptr;
  if (c.analysis == MpmAnalysis::quasi_static) {
    auto q = std::make_unique<QuasiStaticScheme>(c);
    quasi_static = q.get();
    scheme = std::move(q);
  } else {
    scheme = std::make_unique<ExplicitScheme>(c);
  }
  MpmRunSummary summary;
  summary.analysis = c.analysis;
  MpmOutputWriter writer(c, out_dir, *scheme, summary);
  writer.checkpointed_ = hooks.checkpointed;
  if (!restart.empty()) {
    // The case's solver takes the checkpoint's state; the material sets of the phases before
    // apply. (The next phase's settings are set when it begins: the checkpoint is taken at a
    // phase end, and a phase start forgets the cached wave speeds either way.)
    mpm::MpmState& state = scheme->state();
    const MpmCheckpointInfo info = read_mpm_checkpoint(restart, state);
    if (info.next_phase < 1 || static_cast<std::size_t>(info.next_phase) >= c.phases.size())
      throw InputError(restart.string(), 0, "--restart", restart.string(),
                       fmt::format("holds the state after {} phase(s), and the case has {}: "
                                   "nothing left to run",
                                   info.next_phase, c.phases.size()));
    summary.first_phase = static_cast<std::size_t>(info.next_phase);
    if (progress_stream != nullptr && info.threads > 0 && info.threads != state.threads())
      *progress_stream << fmt::format(
          "mpm: the checkpoint was written with {} thread(s), this run has {}: it continues to "
          "round-off, not bitwise\n",
          info.threads, state.threads());
    for (std::size_t k = 0; k < summary.first_phase; ++k)
      for (const MpmMaterialChange& change : c.phases[k].material_changes)
        state.set_material(change.model, change.replacement);
    writer.restore(info, restart);
    for (CheckpointedState* kept : hooks.checkpointed) {
      const auto saved = info.records.find(kept->record_name());
      kept->restore(saved == info.records.end() ? std::string() : saved->second,
                    summary.first_phase, restart);
    }
  }
  ProgressObserver progress(progress_stream, hooks.progress_on_terminal);
  std::vector<RunObserver*> observers{&writer, &progress};
  observers.insert(observers.end(), hooks.observers.begin(), hooks.observers.end());
  summary.phase_ends = run_phases(c, *scheme, summary.first_phase, observers);
  summary.steps = scheme->steps();
  summary.time = scheme->time();
  summary.wall_seconds = progress.wall_seconds();
  if (quasi_static != nullptr) {
    summary.newton_iterations = quasi_static->total_iterations();
    summary.newton_cuts = quasi_static->total_cuts();
    summary.most_newton_iterations = quasi_static->most_iterations();
    summary.newton_accepted = quasi_static->total_accepted();
    summary.largest_accepted_residual = quasi_static->largest_accepted_residual();
    summary.newton_stabilised = quasi_static->total_stabilised();
    summary.newton_rescued = quasi_static->total_rescued();
    summary.max_penetration = quasi_static->max_penetration();
    summary.linear_solver =
        mpm::quasi_static::to_string(quasi_static->solver().linear_solver_kind());
    summary.linear_counts = quasi_static->solver().linear_counts();
  }
  return summary;
}

}  // namespace pilempm
