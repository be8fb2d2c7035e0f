// `pilempm mpm ...`: material point method runs. `run` reads a case file
// (docs/mpm-case-files.md), checks all of it before the first step, runs its phases and writes
// the particle snapshots (VTU + PVD), the energy account and the rigid bodies' motion and forces
// (CSV) into the output folder, and how each phase ended.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include <unistd.h>

#include "cli/commands.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/io/mpm_case.hpp"
#include "pilempm/io/mpm_output.hpp"

namespace pilempm::cli {

namespace {

struct MpmRunFlags {
  std::string case_file;
  std::string out = "mpm-results";
  std::string restart;
  bool quiet = false;
  bool overwrite = false;
};

// A restart continues its own run when its checkpoint lies in the output folder: that folder's
// files are the run's own earlier part, kept.
bool restarts_in_its_own_folder(const MpmRunFlags& flags) {
  if (flags.restart.empty()) return false;
  const auto canonical = [](const std::filesystem::path& path) {
    std::error_code ec;
    std::filesystem::path p = std::filesystem::weakly_canonical(path, ec);
    if (ec) return std::filesystem::path();
    return p.has_filename() ? p : p.parent_path();  // "DIR/" as "DIR"
  };
  const std::filesystem::path folder = canonical(flags.out);
  return !folder.empty() && folder == canonical(flags.restart).parent_path();
}

void run_mpm(const MpmRunFlags& flags) {
  const simulation::MpmCase c = read_mpm_case(flags.case_file);
  double total = 0.0;
  for (const simulation::MpmPhase& phase : c.phases) total += phase.duration;
  fmt::print("{}: {} region{}, {} bod{}, {} phase{}, {} analysis, at most {:.6g} s {} -> {}/\n",
             c.source, c.regions.size(), c.regions.size() == 1 ? "" : "s", c.bodies.size(),
             c.bodies.size() == 1 ? "y" : "ies", c.phases.size(), c.phases.size() == 1 ? "" : "s",
             to_string(c.analysis), total,
             c.analysis == simulation::MpmAnalysis::quasi_static ? "of pseudo-time" : "simulated",
             flags.out);
  std::fflush(stdout);
  OutputFolderOptions folder;
  folder.resume = restarts_in_its_own_folder(flags);
  folder.overwrite = flags.overwrite;
  if (folder.resume && folder.overwrite)
    throw InputError("command line", 0, "--overwrite", "",
                     "not with --restart from a checkpoint in the output folder: it would "
                     "remove the checkpoint (the run's own files there are kept without it)");
  take_output_folder(flags.out, folder);
  MpmRunHooks hooks;
  hooks.progress_on_terminal = isatty(STDERR_FILENO) != 0;
  const MpmRunSummary summary =
      run_mpm_case(c, flags.out, flags.quiet ? nullptr : &std::cerr, flags.restart, hooks);
  if (!flags.restart.empty())
    fmt::print("restarted from {}: phases from \"{}\" on\n", flags.restart,
               c.phases.at(summary.first_phase).name);
  for (const simulation::MpmPhaseEnd& end : summary.phase_ends)
    fmt::print("phase {}: ended at t = {:.6g} s, step {}: {}\n", end.phase, end.time, end.steps,
               end.reason);
  if (summary.analysis == simulation::MpmAnalysis::quasi_static)
    fmt::print(
        "quasi-static: {} load steps, {} Newton iterations ({:.1f} per step, at most {}), {} "
        "cuts, {} accepted above the force tolerance (largest ||R|| {:.2g} F_ref){}{}; largest "
        "contact penetration {:.3g} m\n",
        summary.steps, summary.newton_iterations,
        summary.steps > 0 ? double(summary.newton_iterations) / double(summary.steps) : 0.0,
        summary.most_newton_iterations, summary.newton_cuts, summary.newton_accepted,
        summary.largest_accepted_residual,
        summary.newton_stabilised > 0
            ? fmt::format(", {} sub-increments kept the low-stress stabilisation",
                          summary.newton_stabilised)
            : std::string(),
        summary.newton_rescued > 0
            ? fmt::format(", {} load steps finished with the low-stress stabilisation after "
                          "their cuts ran out",
                          summary.newton_rescued)
            : std::string(),
        summary.max_penetration);
  if (summary.analysis == simulation::MpmAnalysis::quasi_static) {
    const auto& counts = summary.linear_counts;
    fmt::print(
        "linear solver {}: {} factorisations, {} solves{}\n", summary.linear_solver,
        counts.factorisations, counts.solves,
        counts.precision_solves > 0
            ? fmt::format(" ({:.2f} single-precision solves each; {} LUs redone in double "
                          "precision)",
                          double(counts.precision_solves) / double(std::max(counts.solves, 1L)),
                          counts.double_fallbacks)
            : std::string());
  }
  fmt::print(
      "done: {} steps to t = {:.6g} s in {:.2f} s wall; {} snapshots in {}, energies in "
      "{}{}\n",
      summary.steps, summary.time, summary.wall_seconds, summary.vtu_files.size(),
      summary.pvd_file.string(), summary.energies_file.string(),
      summary.bodies_file.empty() ? std::string() : ", bodies in " + summary.bodies_file.string());
  if (!summary.load_steps_file.empty())
    fmt::print("load steps (Newton iterations, cuts, times) in {}\n",
               summary.load_steps_file.string());
}

}  // namespace

void register_mpm_commands(CLI::App& app) {
  CLI::App* mpm = app.add_subcommand("mpm", "material point method simulations");
  mpm->require_subcommand(1);
  auto flags = std::make_shared<MpmRunFlags>();
  CLI::App* run = mpm->add_subcommand(
      "run",
      "run an MPM case file (docs/mpm-case-files.md); writes particles_*.vtu, "
      "particles.pvd (open in ParaView), energies.csv, bodies.csv, load_steps.csv "
      "(quasi-static analysis) and a checkpoint per phase");
  run->add_option("case", flags->case_file, "the case file (TOML)")
      ->required()
      ->type_name("CASE.toml");
  run->add_option("--out", flags->out, "output folder")->capture_default_str()->type_name("DIR");
  run->add_option("--restart", flags->restart,
                  "continue from a checkpoint (checkpoint_NN_<phase>.h5 of an earlier run) with "
                  "the case's phases after it and the case's materials")
      ->type_name("FILE");
  run->add_flag("--quiet", flags->quiet, "no progress lines on stderr");
  add_overwrite_flag(*run, flags->overwrite);
  run->callback([flags]() { run_mpm(*flags); });
}

}  // namespace pilempm::cli
