// The centrifuge run with sand of any model of the library (docs/centrifuge.md, "Sand of any
// model"), on a tiny model (R = 4 D, D/2 mesh, one thread): with Mohr-Coulomb sand, 1.5 D of
// installation, relaxation and load test run and pass the run's own checks (K0 stress,
// equilibrium, kinetic energy, no sand in the pile or across the axis); linear elastic sand does
// the same over 0.75 D of installation (beyond about 1 D the sand that cannot yield around the
// tip throws bursts of kinetic energy of 10 % of the pile's work, docs/centrifuge.md); and the
// elastic case on the quasi-static analysis runs its phases with the head force equal to the
// floor's reaction less the sand's weight to the Newton tolerance, and the mpm_case.toml it writes
// runs with `pilempm mpm run` to the same pile forces.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "../support/centrifuge_case_texts.hpp"
#include "pilempm/io/centrifuge_case.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/mpm_output.hpp"
#include "pilempm/scenario/centrifuge/run_checks.hpp"
#include "pilempm/study/centrifuge_run.hpp"

namespace pilempm {
namespace {

using namespace scenario;
namespace fs = std::filesystem;

// The tiny model of the centrifuge run tests as a case file, with the sand's [[material]] and
// [sand] table and any extra tables.
std::string tiny_case(const std::string& sand, const std::string& installation,
                      const std::string& extra = "") {
  return sand + R"(
[test]
container_radius_D = 4.0
sand_height_D = 8.0
[installation]
)" + installation +
         R"(
[mesh]
cells_per_D = 2
fine_radius_D = 2.0
fine_depth_below_tip_D = 2.0
headroom_D = 1.0
)" + extra;
}

const std::string kMohrCoulombSand = std::string("title = \"tiny, Mohr-Coulomb sand\"\n") +
                                     test_support::kMohrCoulombSandMaterial + R"([sand]
material = "mc-sand"
e0 = 0.68
)";

const char* const kElasticSand = R"(title = "tiny, linear elastic sand"
[[material]]
name = "elastic-sand"
model = "linear-elastic"
young_modulus_MPa = 50.0
poisson_ratio = 0.3
[sand]
material = "elastic-sand"
e0 = 0.68
[pile]
interface_friction_angle_deg = 20.0
)";

struct TinyRun {
  CentrifugeSummary summary;
  std::string summary_md, figures_json;
  // The rigid bodies' record of the run, and of `pilempm mpm run` of the mpm_case.toml it wrote.
  std::string bodies_csv, rerun_bodies_csv;
};

std::string file_text(const fs::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TinyRun run_tiny(const std::string& text, const std::string& name, bool rerun = false) {
  const fs::path dir =
      fs::temp_directory_path() / ("pilempm-sand-" + name + "-" + std::to_string(::getpid()));
  CentrifugeScenario s = read_centrifuge_case_text(text, name + ".toml");
  s.threads = 1;
  CentrifugeRunOptions options;
  options.plots = false;
  TinyRun run;
  run.summary = run_centrifuge(s, text, dir, nullptr, options);
  run.summary_md = file_text(dir / "summary.md");
  run.figures_json = file_text(dir / "figures.json");
  run.bodies_csv = file_text(dir / "mpm" / "bodies.csv");
  if (rerun) {
    (void)run_mpm_case(read_mpm_case(dir / "mpm_case.toml"), dir / "rerun", nullptr);
    run.rerun_bodies_csv = file_text(dir / "rerun" / "bodies.csv");
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
  return run;
}

// Every phase ran to its end and every check that applies passed.
void expect_every_phase_and_check(const TinyRun& run, double tip_depth_D) {
  const CentrifugeSummary& r = run.summary;
  for (const CentrifugeCheck& c : centrifuge_checks(r)) EXPECT_TRUE(c.passed) << c.text();
  EXPECT_NEAR(r.installation_tip_depth_D, tip_depth_D, 0.05);
  EXPECT_GT(r.installation_head_force, 0.0);
  EXPECT_GT(r.capacity, 0.0);  // the load test pushes the pile into the sand
  EXPECT_NEAR(r.load_test_displacement_mm, 0.1 * 11.3, 1e-3);
  EXPECT_GE(r.relaxation_travel_mm, 0.0);
  EXPECT_LE(r.relaxation_travel_mm, 0.05 * 11.3 + 1e-6);
}

TEST(CentrifugeSandModels, MohrCoulombSandRunsEveryPhaseAndPassesItsChecks) {
  const TinyRun run = run_tiny(
      tiny_case(kMohrCoulombSand, "wished_in_place_D = 2.0\ndepth_D = 1.5"), "mohr-coulomb");
  expect_every_phase_and_check(run, 3.5);
  EXPECT_TRUE(std::isfinite(run.summary.max_kinetic_to_work));  // the check applied
  EXPECT_NE(run.summary_md.find("material \"mc-sand\" (mohr-coulomb)"), std::string::npos)
      << run.summary_md;
  // The field figures show e, p and q; the intergranular strain is the hypoplastic model's.
  EXPECT_EQ(run.figures_json.find("igs_rho"), std::string::npos);
  EXPECT_NE(run.figures_json.find("void_ratio"), std::string::npos);
}

TEST(CentrifugeSandModels, LinearElasticSandRunsEveryPhaseAndPassesItsChecks) {
  const TinyRun run = run_tiny(tiny_case(kElasticSand, "wished_in_place_D = 2.0\ndepth_D = 0.75"),
                               "linear-elastic");
  expect_every_phase_and_check(run, 2.75);
  EXPECT_TRUE(std::isfinite(run.summary.equilibrium_error));  // the check applied
  EXPECT_NE(run.summary_md.find("(linear-elastic)"), std::string::npos) << run.summary_md;
}

// The pile starts at the sand surface: wished in place below it, the particle domains that reach
// into the pile are pushed out by the quasi-static analysis's penalty contact in the K0 phase
// (docs/centrifuge.md, "The quasi-static analysis").
TEST(CentrifugeSandModels, ElasticSandRunsItsPhasesOnTheQuasiStaticAnalysis) {
  const TinyRun run =
      run_tiny(tiny_case(kElasticSand, "wished_in_place_D = 0.0\ndepth_D = 1.5",
                         "[solver]\nanalysis = \"quasi-static\"\ndisplacement_step_D = 0.05\n"),
               "quasi-static", /*rerun=*/true);
  expect_every_phase_and_check(run, 1.5);
  // The mpm_case.toml it wrote runs as the centrifuge run ran: the same pile forces, to the bit.
  EXPECT_GT(run.bodies_csv.size(), 1000u);
  EXPECT_EQ(run.rerun_bodies_csv, run.bodies_csv);
  const CentrifugeSummary& r = run.summary;
  // No inertia: the head force is the floor's reaction less the sand's weight in every window,
  // to far better than the explicit analysis's 2 % (the Newton tolerance is 1e-6 of the forces).
  EXPECT_LT(r.equilibrium_error, 1e-4);
  EXPECT_EQ(r.max_kinetic_to_work, 0.0);
  EXPECT_NE(run.summary_md.find("quasi-static analysis"), std::string::npos) << run.summary_md;
}

}  // namespace
}  // namespace pilempm
