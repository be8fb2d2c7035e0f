#include "pilempm/io/calibration_case.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "pilempm/core/number_text.hpp"
#include "pilempm/io/element_case.hpp"
#include "pilempm/io/material_reader.hpp"

namespace pilempm {

namespace fs = std::filesystem;
using calibration::FreeParameter;
using calibration::LabTest;
using calibration::MeasuredQuantity;
using calibration::ParameterId;

namespace {

const std::vector<std::string> kCalibrationTypes = {"isotropic", "oedometer", "triaxial",
                                                    "undrained-triaxial"};
const std::vector<std::string> kMethods = {"ceres-lm", "nlopt-bobyqa"};
const std::vector<std::string> kConventions = {"initial-stress", "zero-pressure"};

std::string trim(std::string_view s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return std::string(s.substr(a, b - a));
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream stream(line);
  std::string cell;
  while (std::getline(stream, cell, ',')) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The column a misnamed one probably meant: the same quantity in another unit or without its
// unit ("q", "q_Pa", "axial_strain" -> "q_kPa", ..., "axial_strain_pct").
std::string guess_column(const std::string& name) {
  const std::string l = lower(name);
  for (const std::string& c : calibration::curve_quantity_columns()) {
    const std::string stem = c.substr(0, c.rfind('_'));
    const std::string l_stem = l.substr(0, l.rfind('_'));
    if (l == lower(c) || l == stem || l_stem == stem || l == c.substr(0, c.find('_'))) return c;
  }
  return "";
}

bool is_stress_column(std::string_view c) {
  return c.size() > 4 && c.substr(c.size() - 4) == "_kPa";
}

double programme_end(const ElementTest& test) {
  if (const auto* t = std::get_if<DrainedTriaxialTest>(&test)) return 100.0 * t->axial_strain;
  if (const auto* t = std::get_if<UndrainedTriaxialTest>(&test)) return 100.0 * t->axial_strain;
  if (const auto* t = std::get_if<IsotropicCompressionTest>(&test)) return t->p_end / 1e3;
  if (const auto* t = std::get_if<OedometerTest>(&test))
    return *std::max_element(t->sigma_v_targets.begin(), t->sigma_v_targets.end()) / 1e3;
  return 0.0;
}

double programme_start(const ElementTest& test) {
  if (const auto* t = std::get_if<IsotropicCompressionTest>(&test)) return t->p0 / 1e3;
  if (const auto* t = std::get_if<OedometerTest>(&test)) return t->sigma_v0 / 1e3;
  return 0.0;
}

bool monotonic_programme(const ElementTest& test) {
  const auto* oedometer = std::get_if<OedometerTest>(&test);
  return oedometer == nullptr || oedometer->sigma_v_targets.size() == 1;
}

std::vector<std::string> parameter_names() {
  std::vector<std::string> names;
  for (ParameterId id : calibration::all_parameters())
    names.emplace_back(calibration::parameter_name(id));
  return names;
}

// [parameters]: name = value fixes it, name = {lower, upper[, start]} frees it.
void read_parameters(TableReader& t, calibration::CalibrationProblem& problem) {
  t.declare(parameter_names());
  for (ParameterId id : calibration::all_parameters()) {
    const std::string key(calibration::parameter_name(id));
    const toml::node* node = t.node(key);
    if (node == nullptr) continue;
    if (calibration::is_igs_parameter(id) && !problem.base.igs.enabled())
      throw t.error(key,
                    "not allowed: the intergranular strain is off (igs = \"none\" in "
                    "[calibration]); choose an IGS set there to fit its parameters");
    if (!node->is_table()) {
      calibration::set(problem.base, id, t.number(key, NumberRange::positive()));
      continue;
    }
    std::optional<TableReader> b = t.table(key);
    b->declare({"lower", "upper", "start"});
    FreeParameter f;
    f.id = id;
    f.lower = b->number("lower", NumberRange::positive());
    f.upper = b->number("upper", NumberRange::above(f.lower));
    if (id == ParameterId::phi_c_deg && f.upper >= 90.0)
      throw b->error("upper", "out of range: phi_c_deg must stay below 90");
    if (id == ParameterId::n && f.upper >= 1.0)
      throw b->error("upper", "out of range: n must stay below 1");
    if ((id == ParameterId::m_R || id == ParameterId::m_T) && f.lower < 1.0)
      throw b->error("lower", "out of range: m_R and m_T must be >= 1");
    f.start = b->optional_number("start", NumberRange::closed(f.lower, f.upper));
    b->check_no_unknown_keys();
    problem.free.push_back(f);
  }
  t.check_no_unknown_keys();
  if (problem.free.empty())
    throw t.table_error(
        "no free parameter: give at least one as name = { lower = ..., upper = "
        "... }");
}

LabTest read_lab_test(TableReader& t, TableReader* defaults, const fs::path& directory,
                      const calibration::CalibrationProblem& problem, bool read_data,
                      fs::path& data_file, std::vector<std::string>& warnings) {
  LabTest lab;
  lab.name = t.string("name");
  if (const std::string problem_text = test_name_problem(lab.name); !problem_text.empty())
    throw t.error("name", problem_text);
  const std::string type = t.choice("type", kCalibrationTypes);
  t.declare({"e0", "e0_at", "igs_initial", "data", "weight", "quantities", "weights", "note"});
  t.declare(element_test_programme_keys(type));
  (void)t.optional_string("note");
  const auto at = [&](std::string_view key) -> TableReader& {
    if (!t.contains(key) && defaults != nullptr && defaults->contains(key)) return *defaults;
    return t;
  };
  TableReader& e0 = at("e0");
  if (!e0.contains("e0")) throw t.missing("e0", "the initial void ratio e0 (> 0) is required");
  lab.initial.e0 = e0.number("e0", NumberRange::positive());
  TableReader& e0_at = at("e0_at");
  if (!e0_at.contains("e0_at"))
    throw t.missing("e0_at",
                    "say which state e0 refers to: \"initial-stress\" or "
                    "\"zero-pressure\" (docs/case-files.md)");
  lab.initial.e0_at = parse_void_ratio_convention(e0_at.choice("e0_at", kConventions), "e0_at");
  read_element_initial_igs(at("igs_initial"), lab.initial);
  lab.weight = at("weight").number_or("weight", 1.0, NumberRange::non_negative());
  lab.test = read_element_test_programme(
      t, type, 1.0 - std::sin(problem.base.hypoplastic.phi_c_deg * kPi / 180.0));
  lab.abscissa_column = calibration::abscissa_column_of(lab.test);

  std::vector<std::string> columns = calibration::default_quantities_of(lab.test);
  if (t.contains("quantities")) {
    const toml::array* array = t.node("quantities")->as_array();
    if (array == nullptr || array->empty())
      throw t.error("quantities", "wrong type: must be a non-empty array of column names");
    columns.clear();
    for (const toml::node& n : *array) {
      const auto name = n.value<std::string>();
      const auto& allowed = calibration::curve_quantity_columns();
      if (!name || std::find(allowed.begin(), allowed.end(), *name) == allowed.end() ||
          *name == lab.abscissa_column)
        throw t.error("quantities",
                      fmt::format("not allowed: each entry must be a curve column other than "
                                  "the controlled \"{}\", one of {}",
                                  lab.abscissa_column, fmt::join(allowed, ", ")));
      columns.push_back(*name);
    }
  }
  for (const std::string& c : columns) lab.quantities.push_back({c, {}, 1.0});
  if (auto w = t.table("weights")) {
    w->declare(columns);
    for (MeasuredQuantity& q : lab.quantities)
      q.weight = w->number_or(q.column, 1.0, NumberRange::non_negative());
    w->check_no_unknown_keys();
  }
  const std::string data = t.string("data");
  data_file = fs::path(data).is_absolute() ? fs::path(data) : directory / data;
  t.check_no_unknown_keys();
  if (read_data) {
    if (!fs::exists(data_file))
      throw t.error("data", fmt::format("no such file: {}", data_file.string()));
    read_measured_curve(data_file, lab, warnings);
  }
  lab.data_source = data_file.string();
  return lab;
}

}  // namespace

void read_measured_curve(const fs::path& file, LabTest& test, std::vector<std::string>& warnings) {
  const std::string name = file.string();
  std::ifstream in(file);
  if (!in) throw InputError(name, 0, "data", name, "cannot be read");
  std::string line;
  long number = 0;
  std::vector<std::string> header;
  long header_line = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trim(line).empty() || trim(line).front() == '#') continue;
    header = split(line);
    header_line = number;
    break;
  }
  if (header.empty())
    throw InputError(name, number, "header", "", "missing: the file has no header line");
  // Every column must be one of pilempm's curve columns (increment and substeps are ignored).
  const auto& known = calibration::curve_quantity_columns();
  std::set<std::string> seen;
  for (const std::string& c : header) {
    if (c == "increment" || c == "substeps") continue;
    if (std::find(known.begin(), known.end(), c) == known.end()) {
      const std::string guess = guess_column(c);
      throw InputError(name, header_line, fmt::format("column \"{}\"", c), c,
                       guess.empty()
                           ? fmt::format("unknown column; the columns of pilempm's curve CSVs are "
                                         "{}",
                                         fmt::join(known, ", "))
                           : fmt::format("unknown column (did you mean \"{}\"? the units are part "
                                         "of the name: strains in per cent, stresses in kPa)",
                                         guess));
    }
    if (!seen.insert(c).second)
      throw InputError(name, header_line, fmt::format("column \"{}\"", c), c, "duplicate column");
  }
  std::vector<std::string> needed = {test.abscissa_column};
  for (const MeasuredQuantity& q : test.quantities) needed.push_back(q.column);
  std::vector<std::size_t> index;
  for (const std::string& c : needed) {
    const auto it = std::find(header.begin(), header.end(), c);
    if (it == header.end())
      throw InputError(
          name, header_line, fmt::format("column \"{}\"", c), "",
          fmt::format("missing: a {} test needs the columns {}; the header has {}",
                      test_type_name(test.test), fmt::join(needed, ", "), fmt::join(header, ", ")));
    index.push_back(static_cast<std::size_t>(it - header.begin()));
  }
  std::vector<std::vector<double>> values(needed.size());
  std::vector<long> lines;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trim(line).empty() || trim(line).front() == '#') continue;
    const std::vector<std::string> cells = split(line);
    if (cells.size() != header.size())
      throw InputError(
          name, number, "row", line,
          fmt::format("wrong number of cells: {} for {} columns", cells.size(), header.size()));
    for (std::size_t k = 0; k < needed.size(); ++k) {
      const std::string& cell = cells[index[k]];
      const std::optional<double> number_read = whole_number(cell);
      if (!number_read)
        throw InputError(name, number, fmt::format("column \"{}\"", needed[k]), cell,
                         "not a number");
      const double v = *number_read;
      if (!std::isfinite(v))
        throw InputError(name, number, fmt::format("column \"{}\"", needed[k]), cell,
                         "not a finite number (NaN or infinity): remove the row or fill it in");
      // Units that cannot be right.
      if (is_stress_column(needed[k]) && std::abs(v) > 1e6)
        throw InputError(name, number, fmt::format("column \"{}\"", needed[k]), cell,
                         "out of range: above 1 GPa; are the stresses in Pa where the column "
                         "name says kPa?");
      if (needed[k] == "void_ratio" && !(v > 0.0 && v < 5.0))
        throw InputError(name, number, fmt::format("column \"{}\"", needed[k]), cell,
                         "out of range: a void ratio must be in (0, 5)");
      values[k].push_back(v);
    }
    lines.push_back(number);
  }
  const std::size_t n = lines.size();
  if (n < 3)
    throw InputError(name, number, "rows", std::to_string(n),
                     "too few points: a measured curve needs at least 3 rows");
  const std::vector<double>& x = values[0];
  const std::string& xc = test.abscissa_column;
  const double end = programme_end(test.test), start = programme_start(test.test);
  const double x_max = *std::max_element(x.begin(), x.end());
  // Strains in fractions where per cent are expected.
  if (xc == "axial_strain_pct" && end >= 2.0 && x_max <= 0.01 * end * 1.0001)
    throw InputError(name, lines.back(), fmt::format("column \"{}\"", xc), format_value(x_max),
                     fmt::format("unit: the test runs to {} % axial strain but the column ends "
                                 "at {}; strains must be in per cent, not fractions",
                                 format_value(end), format_value(x_max)));
  // Stresses in Pa or MPa where kPa are expected.
  if (is_stress_column(xc) && x_max > 100.0 * end)
    throw InputError(name, lines.back(), fmt::format("column \"{}\"", xc), format_value(x_max),
                     fmt::format("unit: far above the test's largest stress {} kPa; are the "
                                 "stresses in Pa?",
                                 format_value(end)));
  if (is_stress_column(xc) && x_max < 0.01 * end)
    throw InputError(name, lines.back(), fmt::format("column \"{}\"", xc), format_value(x_max),
                     fmt::format("unit: far below the test's largest stress {} kPa; are the "
                                 "stresses in MPa?",
                                 format_value(end)));
  // Loading direction and range.
  const double tolerance = 1e-6 * std::max(1.0, std::abs(end));
  if (monotonic_programme(test.test)) {
    for (std::size_t j = 1; j < n; ++j)
      if (x[j] < x[j - 1] - tolerance)
        throw InputError(name, lines[j], fmt::format("column \"{}\"", xc), format_value(x[j]),
                         fmt::format("not monotonic: falls from {} on the line before; a {} test "
                                     "loads monotonically",
                                     format_value(x[j - 1]), test_type_name(test.test)));
    if (x_max > end * 1.001 + tolerance)
      throw InputError(name, lines.back(), fmt::format("column \"{}\"", xc), format_value(x_max),
                       fmt::format("beyond the test's programme, which ends at {}; extend the "
                                   "programme or cut the data",
                                   format_value(end)));
  }
  if (start > 0.0 && x.front() < start * 0.999)
    throw InputError(name, lines.front(), fmt::format("column \"{}\"", xc), format_value(x.front()),
                     fmt::format("below the test's initial stress {} kPa", format_value(start)));
  // A volumetric strain that never leaves a few hundredths of a per cent while the axial strain
  // runs to several per cent is probably in fractions: the fit can go on, so a warning.
  for (std::size_t k = 1; k < needed.size(); ++k) {
    if (needed[k] != "volumetric_strain_pct" || xc != "axial_strain_pct") continue;
    double largest = 0.0;
    for (double v : values[k]) largest = std::max(largest, std::abs(v));
    if (x_max > 2.0 && largest < 0.02)
      warnings.push_back(fmt::format(
          "{}: column \"volumetric_strain_pct\" stays below 0.02 while the axial strain reaches "
          "{} %: is it in fractions rather than per cent?",
          name, format_value(x_max)));
  }
  test.abscissa = x;
  for (std::size_t k = 1; k < needed.size(); ++k) test.quantities[k - 1].values = values[k];
}

std::string measured_curve_csv(const LabTest& test, const std::string& comment) {
  std::string out = "# " + comment + "\n" + test.abscissa_column;
  for (const MeasuredQuantity& q : test.quantities) out += fmt::format(",{}", q.column);
  out += "\n";
  for (std::size_t j = 0; j < test.abscissa.size(); ++j) {
    out += fmt::format("{:.8g}", test.abscissa[j] + 0.0);  // no "-0"
    for (const MeasuredQuantity& q : test.quantities)
      out += fmt::format(",{:.8g}", q.values[j] + 0.0);
    out += "\n";
  }
  return out;
}

CalibrationCase parse_calibration_case(std::string text, const std::string& source_name,
                                       const fs::path& directory, bool read_data) {
  const toml::table document = parse_toml_text(text, source_name);
  TableReader root(document, source_name, "");
  CalibrationCase c;
  calibration::CalibrationProblem& p = c.problem;
  p.source = source_name;
  c.title = root.optional_string("title").value_or("");

  std::optional<TableReader> settings = root.table("calibration");
  if (!settings)
    throw InputError(source_name, 0, "calibration", "",
                     "missing: a calibration case needs a [calibration] table (base set, ...)");
  settings->declare(
      {"name", "base", "igs", "physics_start", "method", "max_iterations", "threads"});
  p.material_name = settings->optional_string("name").value_or("calibrated");
  if (p.material_name.empty() || p.material_name.size() > 100 ||
      !std::all_of(p.material_name.begin(), p.material_name.end(), [](char ch) {
        return std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_' || ch == '.';
      }))
    throw settings->error("name", "not allowed: 1 to 100 letters, digits, '-', '_' or '.'");
  for (const std::string& builtin : hypoplastic_set_names())
    if (builtin == p.material_name)
      throw settings->error("name",
                            "not allowed: the name of a built-in set (parameters.toml "
                            "would clash with it)");
  p.base_set = settings->choice("base", hypoplastic_set_names());
  p.base.hypoplastic = hypoplastic_set(p.base_set);
  if (settings->contains("igs")) {
    const IgsChoice igs = read_igs(*settings, "igs");
    p.igs_base = igs.name;
    p.base.igs = igs.parameters;
  }
  p.physics_start = settings->boolean_or("physics_start", true);
  p.method = settings->optional_choice("method", kMethods).value_or("ceres-lm");
  p.max_iterations = settings->integer_or("max_iterations", p.max_iterations, 1, 10000);
  p.threads = settings->integer_or("threads", p.threads, 1, 256);
  settings->check_no_unknown_keys();

  if (auto integrator = root.table("integrator")) p.integrator = read_integrator(*integrator);

  std::optional<TableReader> parameters = root.table("parameters");
  if (!parameters)
    throw InputError(source_name, 0, "parameters", "",
                     "missing: a [parameters] table says which parameters are free (name = { "
                     "lower = ..., upper = ... }) and which are fixed (name = value)");
  read_parameters(*parameters, p);
  try {
    p.base.hypoplastic.validate();
  } catch (const InvalidValue& e) {
    throw parameters->error_from(e, {{"h_s_Pa", "h_s_MPa"}}, "value from the base set");
  }

  std::optional<TableReader> defaults = root.table("defaults");
  if (defaults) {
    for (const char* key : {"e0", "e0_at", "igs_initial", "weight"}) defaults->contains(key);
    defaults->check_no_unknown_keys();
  }
  std::vector<TableReader> tests = root.tables("test");
  root.check_no_unknown_keys();
  if (tests.empty())
    throw InputError(source_name, 0, "test", "",
                     "missing: a calibration case needs at least one [[test]] with data");
  std::set<std::string> names;
  for (TableReader& t : tests) {
    fs::path data_file;
    LabTest lab = read_lab_test(t, defaults ? &*defaults : nullptr, directory, p, read_data,
                                data_file, c.warnings);
    if (!names.insert(lower(lab.name)).second)
      throw t.error("name", "duplicate: test names must be unique (ignoring case)");
    c.data_files.push_back(data_file);
    p.tests.push_back(std::move(lab));
  }
  if (read_data) {
    std::size_t points = 0;
    for (const LabTest& t : p.tests) points += calibration::residual_count(t);
    if (points < 3 * p.free.size())
      throw InputError(source_name, 0, "parameters", std::to_string(p.free.size()),
                       fmt::format("too few data: {} measured values for {} free parameters; "
                                   "give at least three values per parameter",
                                   points, p.free.size()));
  }
  c.text = std::move(text);
  return c;
}

CalibrationCase read_calibration_case(const fs::path& path, bool read_data) {
  return parse_calibration_case(read_case_text(path), path.string(), path.parent_path(), read_data);
}

}  // namespace pilempm
