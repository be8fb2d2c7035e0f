// HDF5 checkpoints of MPM runs: a run stopped, written, read into a fresh solver and continued
// equals the uninterrupted run bit for bit (verification 7), in plane strain with a plate and in
// axisymmetry with a pile, with one and two threads; a checkpoint continues with another
// parameter set; a checkpoint of another case, an unwritable path and a damaged file are errors
// that name the file and leave the solver as it was.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "../support/files.hpp"
#include "../support/mpm_case_texts.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/mpm_checkpoint.hpp"
#include "pilempm/simulation/case_assembly.hpp"

namespace pilempm {
namespace {

using namespace simulation;

namespace fs = std::filesystem;
using mpm::Geometry;
using mpm::Particles;
using mpm::RigidBody;
using mpm::Solver;
using mpm::Vec2;

constexpr double kPi = std::numbers::pi;

struct CaseOptions {
  Geometry geometry = Geometry::plane_strain;
  int threads = 1;
  std::string material = "original";
  double x_max = 0.4;  // the region's right side [m]
  bool body = true;
};

// A hypoplastic ground with intergranular strain (IGS3) under 20 g with local damping, 8 x 10
// cells of 2 x 2 particles, in plane strain or axisymmetry.
std::string case_text(const CaseOptions& options) {
  using namespace test_support;
  const bool axisymmetric = options.geometry == Geometry::axisymmetric;
  return mpm_case_opening({.geometry = axisymmetric ? "axisymmetric" : "plane-strain",
                           .x_max_m = 0.4,
                           .x_cells = 8,
                           .y_max_m = 0.6,
                           .y_cells = 12,
                           .boundaries = kRollerRightFixedBase,
                           .solver = "gravity_multiplier = 20.0\nlocal_damping = 0.1\nthreads = " +
                                     std::to_string(options.threads) + "\n"}) +
         mpm_region_text({.x_max_m = options.x_max,
                          .density_kg_per_m3 = 1600.0,
                          .material = options.material}) +
         R"(igs = "IGS3"
e0 = 0.75
e0_at = "initial-stress"
[[phase]]
duration_s = 1.0
output_interval_s = 1.0
)";
}

// The solver of the case at time 0 with its rigid body: in plane strain a plate on the left of
// the surface pushed down and sideways with friction, in axisymmetry a conical pile on the axis
// pushed down; both start 1 cm above the surface, within the contact distance (half a cell).
Solver make_solver(const CaseOptions& options) {
  const bool axisymmetric = options.geometry == Geometry::axisymmetric;
  Solver solver = make_mpm_solver(read_mpm_case_text(case_text(options), "checkpoint.toml"));
  if (options.body) {
    if (axisymmetric) {
      RigidBody pile = RigidBody::pile(0.05, 0.51, kPi / 3.0);
      pile.set_friction(std::tan(20.0 * kPi / 180.0));
      pile.set_velocity({0.0, -1.0});
      solver.add_rigid_body(pile);
    } else {
      RigidBody plate = RigidBody::polygon({{0.0, 0.51}, {0.15, 0.51}, {0.15, 0.6}, {0.0, 0.6}});
      plate.set_friction(0.3);
      plate.set_velocity({0.2, -1.0});
      solver.add_rigid_body(plate);
    }
  }
  return solver;
}

void run_steps(Solver& solver, int steps) {
  for (int k = 0; k < steps; ++k) solver.step();
}

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() /
         ("pilempm-checkpoint-" + std::to_string(::getpid()) + "-" + name);
}

// Whether a temporary file of a write of `file` is left in its folder (FILE.<unique>.tmp).
bool has_temporary_file(const fs::path& file) {
  std::error_code ec;
  const std::string stem = file.filename().string() + ".";
  for (const auto& entry : fs::directory_iterator(file.parent_path(), ec)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with(stem) && name.ends_with(".tmp")) return true;
  }
  return false;
}

using test_support::read_text;  // the bytes of a file

// Bitwise equality of two values (NaN included), with the first differing index in the message.
template <class T>
::testing::AssertionResult same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  if (a.size() != b.size())
    return ::testing::AssertionFailure() << "sizes " << a.size() << " and " << b.size();
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a[i], &b[i], sizeof(T)) != 0)
      return ::testing::AssertionFailure() << "first difference at index " << i;
  return ::testing::AssertionSuccess();
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof(double)) == 0;
}

bool same_bits(const Vec2& a, const Vec2& b) {
  return same_bits(a.x(), b.x()) && same_bits(a.y(), b.y());
}

// Every particle field, the run state and the bodies of two solvers, bit for bit.
void expect_same_bits(const Solver& a, const Solver& b, const std::string& label) {
  SCOPED_TRACE(label);
  const Particles& p = a.particles();
  const Particles& q = b.particles();
  EXPECT_TRUE(same_bits(p.position, q.position)) << "position";
  EXPECT_TRUE(same_bits(p.velocity, q.velocity)) << "velocity";
  EXPECT_TRUE(same_bits(p.mass, q.mass)) << "mass";
  EXPECT_TRUE(same_bits(p.initial_volume, q.initial_volume)) << "initial_volume";
  EXPECT_TRUE(same_bits(p.volume, q.volume)) << "volume";
  EXPECT_TRUE(same_bits(p.initial_half_size, q.initial_half_size)) << "initial_half_size";
  EXPECT_TRUE(same_bits(p.half_size, q.half_size)) << "half_size";
  EXPECT_TRUE(same_bits(p.deformation_gradient, q.deformation_gradient)) << "F";
  EXPECT_TRUE(same_bits(p.out_of_plane_stretch, q.out_of_plane_stretch)) << "F_33";
  EXPECT_TRUE(same_bits(p.material, q.material)) << "material";
  EXPECT_TRUE(same_bits(p.external_force, q.external_force)) << "external_force";
  ASSERT_EQ(p.size(), q.size());
  std::size_t state_differences = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const MaterialState& s = p.state[i];
    const MaterialState& t = q.state[i];
    if (std::memcmp(s.stress.data(), t.stress.data(), sizeof(double) * 6) != 0 ||
        !same_bits(s.void_ratio, t.void_ratio) ||
        std::memcmp(s.history.data(), t.history.data(), sizeof(s.history)) != 0)
      ++state_differences;
  }
  EXPECT_EQ(state_differences, 0u) << "particles with another material state";

  const mpm::SolverRunState r = a.run_state();
  const mpm::SolverRunState s = b.run_state();
  EXPECT_TRUE(same_bits(r.time, s.time)) << r.time << " vs " << s.time;
  EXPECT_EQ(r.steps, s.steps);
  for (const auto member :
       {&mpm::Energies::kinetic, &mpm::Energies::internal, &mpm::Energies::external_work,
        &mpm::Energies::damping, &mpm::Energies::contact_work, &mpm::Energies::absorbed})
    EXPECT_TRUE(same_bits(r.energies.*member, s.energies.*member))
        << r.energies.*member << " vs " << s.energies.*member;
  EXPECT_TRUE(same_bits(r.max_wave_speed, s.max_wave_speed));
  EXPECT_EQ(r.wave_speed_step, s.wave_speed_step);
  EXPECT_TRUE(same_bits(r.max_particle_speed, s.max_particle_speed));
  ASSERT_EQ(a.rigid_body_count(), b.rigid_body_count());
  for (int k = 0; k < a.rigid_body_count(); ++k) {
    EXPECT_TRUE(same_bits(a.rigid_body_force(k).total, b.rigid_body_force(k).total));
    EXPECT_TRUE(same_bits(a.rigid_body_force(k).parts, b.rigid_body_force(k).parts));
    EXPECT_TRUE(same_bits(a.rigid_body(k).vertices(), b.rigid_body(k).vertices()));
    EXPECT_TRUE(same_bits(a.rigid_body(k).displacement(), b.rigid_body(k).displacement()));
    EXPECT_TRUE(same_bits(a.rigid_body(k).velocity(), b.rigid_body(k).velocity()));
    EXPECT_TRUE(same_bits(a.rigid_body(k).friction(), b.rigid_body(k).friction()));
    EXPECT_TRUE(same_bits(a.rigid_body(k).contact_distance(), b.rigid_body(k).contact_distance()));
  }
}

// What the run loop stores besides the solver, with awkward records: empty, with NUL bytes, a
// name with a slash.
MpmCheckpointInfo sample_info(const Solver& solver) {
  MpmCheckpointInfo info;
  info.case_source = "cases/checkpoint.toml";
  info.next_phase = 1;
  info.phase_start = solver.time();
  info.initial_position = solver.particles().position;
  info.records["energies.csv"] = "time_s,kinetic_J\n0,0\n1e-4,3.25\n";
  info.records["empty"] = "";
  info.records["vtu/series.pvd"] = std::string("a\0b\0\0", 5);
  return info;
}

// Run A: n1 + n2 steps. Run B: n1 steps, checkpoint, a fresh solver of the same case reads it and
// takes n2 steps. A and B agree bit for bit.
// n1 is not a multiple of the wave-speed interval (10 steps), so that B's first steps use the
// cached wave speed of the checkpoint.
void check_bitwise_restart(const CaseOptions& options, const std::string& label, int n1 = 35,
                           int n2 = 35) {
  Solver a = make_solver(options);
  run_steps(a, n1 + n2);

  const fs::path file = temp_file(label + ".h5");
  MpmCheckpointInfo written;
  {
    Solver first = make_solver(options);
    run_steps(first, n1);
    written = sample_info(first);
    write_mpm_checkpoint(file, first, written);
  }
  EXPECT_FALSE(has_temporary_file(file));
  Solver b = make_solver(options);
  const Particles start = b.particles();
  const MpmCheckpointInfo read = read_mpm_checkpoint(file, b);
  EXPECT_EQ(b.steps(), n1);
  EXPECT_FALSE(same_bits(b.particles().position, start.position));  // the checkpoint moved them
  run_steps(b, n2);
  expect_same_bits(a, b, label);

  // The run exercised the contact: the soil pushes the body back.
  EXPECT_GT(a.rigid_body_force(0).total.y(), 0.0) << label;

  EXPECT_EQ(read.case_source, written.case_source);
  EXPECT_EQ(read.next_phase, written.next_phase);
  EXPECT_TRUE(same_bits(read.phase_start, written.phase_start));
  EXPECT_TRUE(same_bits(read.initial_position, written.initial_position));
  EXPECT_EQ(read.records, written.records);
  EXPECT_EQ(read.threads, options.threads);
  std::printf("[ checkpoint %s ] %zu particles, %ld steps, file %ju bytes\n", label.c_str(),
              a.particles().size(), a.steps(), static_cast<std::uintmax_t>(fs::file_size(file)));
  fs::remove(file);
}

TEST(MpmCheckpoint, RestartIsBitwiseInPlaneStrainWithPlate) {
  check_bitwise_restart({}, "plane-strain");
}

TEST(MpmCheckpoint, RestartIsBitwiseInPlaneStrainWithTwoThreads) {
  CaseOptions options;
  options.threads = 2;
  // Fewer steps: two threads crawl on a loaded machine (spinning at the barriers).
  check_bitwise_restart(options, "plane-strain-2-threads", 15, 15);
}

TEST(MpmCheckpoint, RestartIsBitwiseInAxisymmetryWithPile) {
  CaseOptions options;
  options.geometry = Geometry::axisymmetric;
  check_bitwise_restart(options, "axisymmetric");
}

// The materials come from the case: a checkpoint read into a solver with another parameter set
// gives every particle the checkpoint's stress, void ratio and intergranular strain, and the run
// continues with the new parameters.
TEST(MpmCheckpoint, ContinuesWithAnotherParameterSet) {
  const fs::path file = temp_file("parameters.h5");
  Solver original = make_solver({});
  run_steps(original, 30);
  write_mpm_checkpoint(file, original, sample_info(original));

  CaseOptions loose;
  loose.material = "loose-fit";  // h_s half that of "original"
  Solver other = make_solver(loose);
  EXPECT_FALSE(same_bits(other.particles().position, original.particles().position));
  read_mpm_checkpoint(file, other);
  expect_same_bits(original, other, "read with loose-fit");

  run_steps(original, 20);
  run_steps(other, 20);
  EXPECT_EQ(other.steps(), 50);
  double largest_difference = 0.0, largest_stress = 0.0;
  for (std::size_t p = 0; p < other.particles().size(); ++p) {
    const Vec6& s = other.particles().state[p].stress;
    ASSERT_TRUE(s.allFinite()) << "particle " << p;
    largest_difference =
        std::max(largest_difference, (s - original.particles().state[p].stress).norm());
    largest_stress = std::max(largest_stress, s.norm());
  }
  // The softer set gives another stress path from the same state.
  EXPECT_GT(largest_difference, 1e-6 * largest_stress);
  fs::remove(file);
}

// Nothing to store besides the solver: empty datasets and groups read back as empty.
TEST(MpmCheckpoint, EmptyRunInfoRoundTrips) {
  const fs::path file = temp_file("empty-info.h5");
  Solver solver = make_solver({});
  run_steps(solver, 3);
  MpmCheckpointInfo info;
  info.case_source = "";
  write_mpm_checkpoint(file, solver, info);
  Solver fresh = make_solver({});
  const MpmCheckpointInfo read = read_mpm_checkpoint(file, fresh);
  EXPECT_TRUE(read.initial_position.empty());
  EXPECT_TRUE(read.records.empty());
  EXPECT_EQ(read.case_source, "");
  EXPECT_EQ(read.next_phase, 0);
  expect_same_bits(solver, fresh, "empty run info");
  // An initial position per particle or none: anything else cannot be written.
  info.initial_position.assign(3, Vec2::Zero());
  EXPECT_THROW(write_mpm_checkpoint(file, solver, info), Error);
  EXPECT_FALSE(has_temporary_file(file));
  fs::remove(file);
}

// Reads `file` into `solver`, expecting an InputError naming the file and `what`; the solver is
// left as it was.
void expect_rejected(const fs::path& file, Solver& solver, const std::string& what) {
  const Particles before = solver.particles();
  const double time = solver.time();
  try {
    read_mpm_checkpoint(file, solver);
    ADD_FAILURE() << "no error for " << what;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
    std::printf("[ rejected ] %s\n", message.c_str());
  }
  EXPECT_TRUE(same_bits(solver.particles().position, before.position)) << what;
  EXPECT_TRUE(same_bits(solver.particles().velocity, before.velocity)) << what;
  EXPECT_TRUE(same_bits(solver.time(), time)) << what;
  EXPECT_EQ(solver.steps(), 0) << what;
}

TEST(MpmCheckpoint, CheckpointOfAnotherCaseIsAnErrorNamingTheMismatch) {
  const fs::path file = temp_file("mismatch.h5");
  Solver solver = make_solver({});
  run_steps(solver, 5);
  write_mpm_checkpoint(file, solver, sample_info(solver));

  CaseOptions narrower;
  narrower.x_max = 0.3;  // 6 columns of cells instead of 8
  Solver fewer_particles = make_solver(narrower);
  expect_rejected(file, fewer_particles, "particle_count = 320: the case has 240 particles");

  CaseOptions axisymmetric;
  axisymmetric.geometry = Geometry::axisymmetric;
  Solver other_geometry = make_solver(axisymmetric);
  expect_rejected(file, other_geometry, "geometry = plane-strain: the case is axisymmetric");

  CaseOptions no_body;
  no_body.body = false;
  Solver without_body = make_solver(no_body);
  expect_rejected(file, without_body, "body_count = 1: the case has 0 rigid bodies");

  CaseOptions triangle;
  triangle.body = false;
  Solver other_body = make_solver(triangle);
  other_body.add_rigid_body(RigidBody::polygon({{0.0, 0.51}, {0.15, 0.51}, {0.0, 0.6}}));
  expect_rejected(file, other_body, "/bodies/0/vertices = 4 vertices");
  fs::remove(file);
}

TEST(MpmCheckpoint, UnwritablePathIsAnErrorAndLeavesNoTemporaryFile) {
  const Solver solver = make_solver({});
  const MpmCheckpointInfo info = sample_info(solver);
  // A folder that does not exist: the temporary file cannot be made.
  const fs::path missing = temp_file("no-such-folder") / "checkpoint.h5";
  try {
    write_mpm_checkpoint(missing, solver, info);
    ADD_FAILURE() << "no error for " << missing;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(has_temporary_file(missing));
  // A folder where the file should go: the file is written but cannot be renamed onto it.
  const fs::path folder = temp_file("folder.h5");
  fs::create_directories(folder);
  try {
    write_mpm_checkpoint(folder, solver, info);
    ADD_FAILURE() << "no error for " << folder;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(folder.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(has_temporary_file(folder));
  EXPECT_TRUE(fs::is_directory(folder));
  fs::remove_all(folder);
}

TEST(MpmCheckpoint, DamagedOrForeignFileIsAnInputError) {
  Solver solver = make_solver({});
  const fs::path text = temp_file("text.h5");
  std::ofstream(text) << "time_s,kinetic_J\n0,0\n";
  expect_rejected(text, solver, "not an HDF5 file");

  expect_rejected(temp_file("absent.h5"), solver, "no such checkpoint file");

  // A checkpoint cut short, as by a full disk without the atomic rename.
  const fs::path whole = temp_file("whole.h5");
  const fs::path cut = temp_file("cut.h5");
  write_mpm_checkpoint(whole, solver, sample_info(solver));
  const std::string bytes = read_text(whole);
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  expect_rejected(cut, solver, cut.string());
  fs::remove(text);
  fs::remove(whole);
  fs::remove(cut);
}

// Bits flipped in a checkpoint (1 to 16, anywhere in the file, seeded): the restart is refused
// with a message naming the file, or, where the flips hit bytes that hold nothing the reader
// uses, it gives exactly the solver that was written. Before the checksums, 33 of 80 damaged
// checkpoints restarted silently with other results.
TEST(MpmCheckpoint, FlippedBitsAreRefusedOrChangeNothing) {
  Solver written = make_solver({});
  run_steps(written, 35);
  const MpmCheckpointInfo info = sample_info(written);
  const fs::path whole = temp_file("flip-whole.h5");
  const fs::path damaged = temp_file("flip-damaged.h5");
  write_mpm_checkpoint(whole, written, info);
  const std::string bytes = read_text(whole);
  std::uint64_t seed = 2025;
  const auto next = [&seed]() {  // a 64-bit linear congruential generator (Knuth's MMIX)
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return seed >> 33;
  };
  int refused = 0, unchanged = 0, named_dataset = 0;
  const int trials = 400;
  for (int trial = 0; trial < trials; ++trial) {
    std::string copy = bytes;
    // Half the trials flip one bit at evenly spread places, half 2 to 16 bits anywhere.
    const int flips = trial % 2 == 0 ? 1 : 2 + static_cast<int>(next() % 15);
    for (int f = 0; f < flips; ++f) {
      const std::size_t at = flips == 1 ? (static_cast<std::size_t>(trial) * bytes.size()) / trials
                                        : next() % bytes.size();
      copy[at] = static_cast<char>(copy[at] ^ (1 << (next() % 8)));
    }
    std::ofstream(damaged, std::ios::binary | std::ios::trunc) << copy;
    Solver restarted = make_solver({});
    try {
      const MpmCheckpointInfo read = read_mpm_checkpoint(damaged, restarted);
      ++unchanged;
      SCOPED_TRACE(fmt::format("trial {}: {} flips, accepted", trial, flips));
      expect_same_bits(written, restarted, "damaged but accepted");
      EXPECT_EQ(read.case_source, info.case_source);
      EXPECT_EQ(read.next_phase, info.next_phase);
      EXPECT_TRUE(same_bits(read.phase_start, info.phase_start));
      EXPECT_TRUE(same_bits(read.initial_position, info.initial_position));
      EXPECT_EQ(read.records, info.records);
      if (::testing::Test::HasFailure()) break;
    } catch (const InputError& e) {
      ++refused;
      const std::string message = e.what();
      EXPECT_NE(message.find(damaged.string()), std::string::npos) << message;
      if (message.find("damaged: its data do not match the checksum") != std::string::npos) {
        ++named_dataset;
        EXPECT_NE(message.find(": /"), std::string::npos) << message;  // the dataset's path
      }
    }
  }
  std::printf(
      "[ bit flips ] %d trials on %zu bytes: %d refused (%d by a dataset's checksum), %d "
      "accepted unchanged\n",
      trials, bytes.size(), refused, named_dataset, unchanged);
  EXPECT_GT(named_dataset, 0);
  fs::remove(whole);
  fs::remove(damaged);
}

TEST(MpmCheckpoint, DamagedDatasetIsRefusedNamingIt) {
  // The stress of the last particle is the last double of /particles/stress: find its bytes in
  // the file and change one.
  Solver written = make_solver({});
  run_steps(written, 5);
  const fs::path file = temp_file("stress-damaged.h5");
  write_mpm_checkpoint(file, written, sample_info(written));
  std::string bytes = read_text(file);
  const Particles& p = written.particles();
  const std::size_t last = p.size() - 1;
  std::string needle(6 * sizeof(double), '\0');
  std::memcpy(needle.data(), p.state[last].stress.data(), needle.size());
  const std::size_t at = bytes.find(needle);
  ASSERT_NE(at, std::string::npos);
  bytes[at + 3] = static_cast<char>(bytes[at + 3] ^ 0x10);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  Solver restarted = make_solver({});
  expect_rejected(file, restarted, "/particles/stress: damaged");
  fs::remove(file);
}

}  // namespace
}  // namespace pilempm
