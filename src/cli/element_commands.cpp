// `pilempm element ...`: element tests at a single material point. `run` runs a case file (the
// built-in examples/element_tests.toml when none is given); `triaxial`, `undrained`,
// `oedometer` and `isotropic` run one test from flags. Flags are taken as text and checked here,
// so that every bad value gives one message with the flag, the value and the allowed range.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <CLI/CLI.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "pilempm/io/element_case.hpp"
#include "pilempm/io/element_output.hpp"
#include "pilempm/io/element_run.hpp"
#include "pilempm/io/material_reader.hpp"
#include "pilempm/io/output/atomic_file.hpp"

namespace pilempm::cli {

namespace {

constexpr double kKPa = 1.0e3;
constexpr const char* kCommandLine = "command line";

InputError flag_error(const std::string& flag, const std::string& value,
                      const std::string& reason) {
  return InputError(kCommandLine, 0, flag, value, reason);
}

double parse_number(const std::string& flag, const std::string& text, const NumberRange& range) {
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE)
    throw flag_error(flag, text, "not a number");
  if (const std::string problem = range.problem(value); !problem.empty())
    throw flag_error(flag, text, problem);
  return value;
}

int parse_integer(const std::string& flag, const std::string& text, int min, int max) {
  errno = 0;
  char* end = nullptr;
  const long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE)
    throw flag_error(flag, text, "not an integer");
  if (value < min || value > max)
    throw flag_error(flag, text,
                     fmt::format("out of range: must be an integer in [{}, {}]", min, max));
  return static_cast<int>(value);
}

std::string parse_choice(const std::string& flag, const std::string& text,
                         const std::vector<std::string>& allowed) {
  for (const auto& a : allowed)
    if (a == text) return text;
  throw flag_error(flag, text,
                   fmt::format("not allowed: must be one of {}", fmt::join(allowed, ", ")));
}

// The flags every single-test command shares; all text until checked.
struct CommonFlags {
  std::string set, igs, igs_initial = "compression", e0, e0_at, tolerance, scheme, steps, name;
  std::string out, summary;
};

// The flags of one test type, name -> text.
struct TestFlags {
  std::string sigma3, p0, p_end, axial_strain, sigma_v0, K0, sigma_v;
};

void add_common_flags(CLI::App* sub, CommonFlags& f, const char* default_steps) {
  sub->add_option("--set", f.set,
                  "hypoplastic parameter set (required): " +
                      fmt::format("{}", fmt::join(hypoplastic_set_names(), ", ")));
  sub->add_option(
      "--igs", f.igs,
      "intergranular strain (required): " + fmt::format("{}", fmt::join(igs_choice_names(), ", ")));
  sub->add_option("--igs-initial", f.igs_initial,
                  "initial intergranular strain: compression (fully mobilised by the isotropic "
                  "compression that made the sample), zero, or first-increment (fully mobilised "
                  "along the test's first strain increment)")
      ->capture_default_str();
  sub->add_option("--e0", f.e0, "initial void ratio (required)");
  sub->add_option("--e0-at", f.e0_at,
                  "which state e0 refers to (required): initial-stress (e0 is the void ratio at "
                  "the initial stress) or zero-pressure (e0 at p = 0, scaled to the initial stress "
                  "by Bauer's law, as the UMAT does)");
  sub->add_option("--steps", f.steps, fmt::format("increments (default {})", default_steps));
  sub->add_option("--tolerance", f.tolerance,
                  "relative local error of the integrator per sub-step, in (0, 0.1] (default "
                  "1e-3)");
  sub->add_option("--scheme", f.scheme, "integrator: heun-euler (default) or bogacki-shampine");
  sub->add_option("--name", f.name, "test name in the summary (default: the test type)");
  sub->add_option("--out", f.out, "curve CSV to write (compression positive, units in the header)");
  sub->add_option("--summary", f.summary, "summary JSON to write");
}

const std::string& required(const std::string& flag, const std::string& value,
                            const std::string& what) {
  if (value.empty()) throw flag_error(flag, "", "missing: " + what);
  return value;
}

// Builds the case from the flags, checking every value.
ElementCase build_case(const std::string& type, const CommonFlags& f, const TestFlags& t) {
  ElementCase c;
  c.name = f.name.empty() ? type : f.name;
  if (const std::string problem = test_name_problem(c.name); !problem.empty())
    throw flag_error("--name", c.name, problem);
  c.source = kCommandLine;

  required(
      "--set", f.set,
      fmt::format("give the parameter set, one of {}", fmt::join(hypoplastic_set_names(), ", ")));
  c.material = builtin_material(parse_choice("--set", f.set, hypoplastic_set_names()));
  required(
      "--igs", f.igs,
      fmt::format("give the intergranular strain, one of {}", fmt::join(igs_choice_names(), ", ")));
  c.igs = named_igs(parse_choice("--igs", f.igs, igs_choice_names()));
  const std::string igs_initial =
      parse_choice("--igs-initial", f.igs_initial, {"compression", "zero", "first-increment"});
  c.initial.igs = igs_initial == "zero"              ? InitialCondition::Igs::zero
                  : igs_initial == "first-increment" ? InitialCondition::Igs::first_increment
                                                     : InitialCondition::Igs::compression;
  c.initial.e0 =
      parse_number("--e0", required("--e0", f.e0, "give the initial void ratio e0 (> 0)"),
                   NumberRange::positive());
  required("--e0-at", f.e0_at,
           "say which state e0 refers to: --e0-at initial-stress (e0 is the void ratio at the "
           "test's initial stress) or --e0-at zero-pressure (e0 is scaled from p = 0 to the "
           "initial stress by Bauer's law, as the UMAT does)");
  c.initial.e0_at = parse_void_ratio_convention(
      parse_choice("--e0-at", f.e0_at, {"initial-stress", "zero-pressure"}), "--e0-at");

  if (!f.tolerance.empty())
    c.integrator.tolerance =
        parse_number("--tolerance", f.tolerance, NumberRange::left_open(0.0, 0.1));
  if (!f.scheme.empty())
    c.integrator.scheme = parse_integrator_scheme(
        parse_choice("--scheme", f.scheme, {"heun-euler", "bogacki-shampine"}), "--scheme");

  const NumberRange positive = NumberRange::positive();
  const NumberRange strain = NumberRange::open(0.0, 1.0);
  const auto steps_or = [&f](int fallback) {
    return f.steps.empty() ? fallback : parse_integer("--steps", f.steps, 1, 10'000'000);
  };
  const auto kpa = [&](const char* flag, const std::string& text) {
    return parse_number(flag, required(flag, text, "a stress in kPa (> 0) is required"), positive) *
           kKPa;
  };
  if (type == "triaxial") {
    DrainedTriaxialTest x;
    x.sigma3 = kpa("--sigma3-kPa", t.sigma3);
    if (!t.axial_strain.empty())
      x.axial_strain = parse_number("--axial-strain", t.axial_strain, strain);
    x.steps = steps_or(x.steps);
    c.test = x;
  } else if (type == "undrained") {
    UndrainedTriaxialTest x;
    x.p0 = kpa("--p0-kPa", t.p0);
    if (!t.axial_strain.empty())
      x.axial_strain = parse_number("--axial-strain", t.axial_strain, strain);
    x.steps = steps_or(x.steps);
    c.test = x;
  } else if (type == "oedometer") {
    OedometerTest x;
    x.sigma_v0 = kpa("--sigma-v0-kPa", t.sigma_v0);
    // Jaky's K0 = 1 - sin(phi_c) unless given.
    x.K0 = t.K0.empty() ? 1.0 - std::sin(c.material.hypoplastic().phi_c_deg * kPi / 180.0)
                        : parse_number("--K0", t.K0, NumberRange::left_open(0.0, 5.0));
    required("--sigma-v-kPa", t.sigma_v,
             "the vertical stress targets in kPa, e.g. 400 or 400,100,400");
    x.sigma_v_targets.clear();
    std::size_t begin = 0;
    while (begin <= t.sigma_v.size()) {
      const std::size_t comma = std::min(t.sigma_v.find(',', begin), t.sigma_v.size());
      x.sigma_v_targets.push_back(
          parse_number("--sigma-v-kPa", t.sigma_v.substr(begin, comma - begin), positive) * kKPa);
      begin = comma + 1;
    }
    x.steps_per_segment = steps_or(x.steps_per_segment);
    c.test = x;
  } else {  // isotropic
    IsotropicCompressionTest x;
    x.p0 = kpa("--p0-kPa", t.p0);
    x.p_end = kpa("--p-end-kPa", t.p_end);
    x.steps = steps_or(x.steps);
    c.test = x;
  }
  c.model = make_model(c.material, c.igs, c.integrator);
  if (const std::string problem = initial_void_ratio_problem(c); !problem.empty())
    throw flag_error("--e0", f.e0, problem);
  return c;
}

void print_single_summary(const ElementRunRecord& r) {
  const ElementCase& c = *r.test;
  const ElementSummary& s = r.summary;
  fmt::print("{} test, set {}, igs {}: e0 = {} ({}) -> e = {:.4f} at p0 = {:.6g} kPa\n",
             test_type_name(c.test), c.material.name, c.igs ? c.igs->name : "none",
             format_value(c.initial.e0), to_string(c.initial.e0_at), s.initial_void_ratio,
             s.initial_p / kKPa);
  if (std::holds_alternative<DrainedTriaxialTest>(c.test) ||
      std::holds_alternative<UndrainedTriaxialTest>(c.test)) {
    fmt::print("peak q = {:.6g} kPa at axial strain {:.3f} %{}: phi_mob = {:.2f} deg",
               s.peak_q / kKPa, 100.0 * s.axial_strain_at_peak,
               s.peak_at_end ? " (the end: no peak reached)" : "", s.phi_at_peak_deg);
    if (std::holds_alternative<DrainedTriaxialTest>(c.test))
      fmt::print(", d eps_v/d eps_1 = {:.4f}, psi = {:.2f} deg", s.dilatancy_ratio_at_peak,
                 s.psi_at_peak_deg);
    fmt::print("\n");
  }
  fmt::print(
      "final: axial strain {:.3f} %, volumetric strain {:.3f} %, sigma_a = {:.6g} kPa, "
      "sigma_r = {:.6g} kPa, e = {:.4f}\n",
      100.0 * s.final.axial_strain, 100.0 * s.final.volumetric_strain, s.final.axial_stress / kKPa,
      s.final.radial_stress / kKPa, s.final.void_ratio);
  fmt::print(
      "{} increments, {} sub-steps, {} mean-stress floor hits, max void-ratio excess {:.2g}; "
      "{:.2f} s\n",
      s.increments, s.substeps, s.mean_stress_floor_hits, s.max_void_ratio_excess, r.seconds);
  if (!r.curve_file.empty()) fmt::print("curve: {}\n", r.curve_file.string());
  if (!r.summary_file.empty()) fmt::print("summary: {}\n", r.summary_file.string());
}

void add_single_test_command(CLI::App& element, const std::string& type,
                             const std::string& description, const char* default_steps) {
  CLI::App* sub = element.add_subcommand(type, description);
  auto common = std::make_shared<CommonFlags>();
  auto test = std::make_shared<TestFlags>();
  add_common_flags(sub, *common, default_steps);
  if (type == "triaxial") {
    sub->add_option("--sigma3-kPa", test->sigma3, "cell pressure [kPa] (required)");
    sub->add_option("--axial-strain", test->axial_strain,
                    "final axial strain, compression positive, in (0, 1) (default 0.2)");
  } else if (type == "undrained") {
    sub->add_option("--p0-kPa", test->p0, "isotropic consolidation stress [kPa] (required)");
    sub->add_option("--axial-strain", test->axial_strain,
                    "final axial strain, compression positive, in (0, 1) (default 0.1)");
  } else if (type == "oedometer") {
    sub->add_option("--sigma-v0-kPa", test->sigma_v0, "initial vertical stress [kPa] (required)");
    sub->add_option("--K0", test->K0,
                    "initial lateral stress ratio (default: Jaky's 1 - sin(phi_c) of the set)");
    sub->add_option("--sigma-v-kPa", test->sigma_v,
                    "vertical stress targets [kPa], comma separated: 400 (monotonic) or "
                    "400,100,400 (cyclic) (required)");
  } else {
    sub->add_option("--p0-kPa", test->p0, "initial mean stress [kPa] (required)");
    sub->add_option("--p-end-kPa", test->p_end, "final mean stress [kPa] (required)");
  }
  // What each flag takes, for --help (the values are read as text and checked here).
  for (CLI::Option* option : sub->get_options()) {
    const std::string& flag = option->get_name();
    if (flag == "--help") continue;
    if (flag == "--steps")
      option->type_name("INT");
    else if (flag == "--sigma-v-kPa")
      option->type_name("LIST");
    else if (flag == "--out" || flag == "--summary")
      option->type_name("FILE");
    else if (flag == "--set" || flag == "--igs" || flag == "--igs-initial" || flag == "--e0-at" ||
             flag == "--scheme" || flag == "--name")
      option->type_name("NAME");
    else
      option->type_name("NUMBER");
  }
  sub->callback([type, common, test]() {
    const ElementCase c = build_case(type, *common, *test);
    // Check the destinations before the run, so that a long run never ends unable to write.
    if (!common->out.empty()) check_output_file(common->out);
    if (!common->summary.empty()) check_output_file(common->summary);
    const ElementRunRecord r = run_and_write(c, common->out, common->summary);
    if (!r.ok) throw Error(fmt::format("{} test failed: {}", type, r.error));
    print_single_summary(r);
  });
}

struct RunFlags {
  std::string case_file;
  std::string out = "element-results";
  std::vector<std::string> only;
  bool overwrite = false;
};

void run_case(const RunFlags& flags) {
  // Everything in the case file is checked here, before any test runs.
  const ElementCaseFile file =
      flags.case_file.empty() ? builtin_element_case() : read_element_case_file(flags.case_file);
  const std::size_t total = select_tests(file, flags.only).size();
  fmt::print("{}: {} test{} -> {}/\n", file.source, total, total == 1 ? "" : "s", flags.out);
  std::fflush(stdout);
  OutputFolderOptions folder;
  folder.overwrite = flags.overwrite;
  take_output_folder(flags.out, folder);
  ElementRunObserver observer;
  const int digits = static_cast<int>(std::to_string(total).size());
  observer.started = [digits](std::size_t index, std::size_t count, const ElementCase& c) {
    fmt::print("[{:>{}}/{}] {} ... ", index, digits, count, c.name);
    std::fflush(stdout);
  };
  observer.finished = [](std::size_t, std::size_t, const ElementRunRecord& r) {
    if (r.ok)
      fmt::print("{:.2f} s -> {}\n", r.seconds, r.curve_file.string());
    else
      fmt::print("FAILED after {:.2f} s: {}\n", r.seconds, r.error);
    std::fflush(stdout);
  };
  const ElementRunReport report = run_element_case(file, flags.out, flags.only, observer);
  fmt::print("\n{}\n", summary_table_text(report.records));
  fmt::print("summary: {} and {} (case: {}); {} test{} in {:.1f} s\n", report.summary_csv.string(),
             report.summary_markdown.string(), report.case_copy.string(), report.records.size(),
             report.records.size() == 1 ? "" : "s", report.seconds);
  if (report.failures > 0)
    throw Error(fmt::format("{} of {} tests failed (see above and {})", report.failures,
                            report.records.size(), report.summary_csv.string()));
}

}  // namespace

void register_element_commands(CLI::App& app) {
  CLI::App* element = app.add_subcommand(
      "element", "element tests at a single material point (oedometer, triaxial, ...)");
  element->require_subcommand(1);

  CLI::App* run = element->add_subcommand(
      "run", "run every test of a case file (default: the built-in examples/element_tests.toml)");
  auto flags = std::make_shared<RunFlags>();
  run->add_option("case", flags->case_file, "case file (TOML, see docs/case-files.md)")
      ->type_name("CASE.toml");
  run->add_option("--out", flags->out, "output folder")->capture_default_str()->type_name("DIR");
  run->add_option("--only", flags->only, "run only these tests (repeat or separate by commas)")
      ->delimiter(',')
      ->type_name("NAME");
  add_overwrite_flag(*run, flags->overwrite);
  run->callback([flags]() { run_case(*flags); });

  add_single_test_command(*element, "triaxial",
                          "drained triaxial compression at constant cell pressure", "2000");
  add_single_test_command(*element, "undrained", "undrained (constant volume) triaxial compression",
                          "2000");
  add_single_test_command(*element, "oedometer", "oedometer (1D compression), monotonic or cyclic",
                          "200 per segment");
  add_single_test_command(*element, "isotropic", "isotropic compression", "400");
}

}  // namespace pilempm::cli
