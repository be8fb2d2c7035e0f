#pragma once
// Element-test case files (format: docs/case-files.md). A case file is a list of [[test]]
// tables, each one element test of element_tests.hpp with its material, intergranular strain,
// initial void ratio and its convention; [defaults] fills keys a test leaves out; [[material]]
// and [integrator] define the models. Everything is checked while reading, so that an error in
// the file stops the run before any test starts.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/element/element_tests.hpp"
#include "pilempm/io/material_reader.hpp"

namespace pilempm {

/// One element test, ready to run.
struct ElementCase {
  std::string name;  ///< unique in its file, safe as a file name
  ElementTest test;
  InitialCondition initial;
  MaterialSpec material;
  std::optional<IgsChoice> igs;  ///< hypoplastic only; nullopt for other models
  IntegratorSettings integrator;
  ModelPtr model;
  std::string note;
  std::string source;  ///< "file:line" of the [[test]] table ("command line" for the CLI)
};

/// A whole case file.
struct ElementCaseFile {
  std::string source;  ///< the file's path, or the built-in name
  std::string text;    ///< the TOML text that was read (copied next to the results)
  std::string title;   ///< optional title = "..." of the file
  std::vector<ElementCase> tests;
};

/// Reads and checks a case file. Throws InputError naming file, line, key, value and range.
ElementCaseFile read_element_case_file(const std::filesystem::path& path);
/// The same for TOML text; `source_name` is what messages call the file.
ElementCaseFile parse_element_case(std::string text, const std::string& source_name);

/// The example case examples/element_tests.toml, compiled into the program.
ElementCaseFile builtin_element_case();
std::string_view builtin_element_case_text();
/// What messages call the built-in case.
inline constexpr const char* kBuiltinElementCaseName = "<built-in examples/element_tests.toml>";

/// The test types of case files ("isotropic", "oedometer", ...) and the programme keys of each.
const std::vector<std::string>& element_test_types();
std::vector<std::string> element_test_programme_keys(const std::string& type);
/// Reads and checks the loading programme of a test table of the given type (used by other case
/// readers, e.g. calibration cases); `jaky_K0` is the oedometer's default K0 (nullopt: required).
ElementTest read_element_test_programme(TableReader& table, const std::string& type,
                                        std::optional<double> jaky_K0);
/// Reads the optional igs_initial key (a name or a tensor) into `initial`.
void read_element_initial_igs(TableReader& table, InitialCondition& initial);

/// Why a test name cannot be used ("" when it can): it names output files, so it must be 1 to
/// 100 characters of letters, digits, '-', '_', '.', start with a letter or digit, and not be
/// one of the names the output uses for itself ("summary", "case").
std::string test_name_problem(std::string_view name);

/// The initial stress of a test (SI, tension positive).
Vec6 initial_stress_of(const ElementTest& test);

/// Checks that the starting void ratio of a hypoplastic test lies in [e_d, e_i] at the initial
/// mean stress; returns the problem ("" when fine). Also used by the command line.
std::string initial_void_ratio_problem(const ElementCase& element_case);

}  // namespace pilempm
