#include "pilempm/io/element_case.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "pilempm/io/default_element_case.hpp"  // generated from examples/element_tests.toml

namespace pilempm {

namespace {

constexpr double kKPa = 1.0e3;
constexpr int kMaxSteps = 10'000'000;

const std::vector<std::string> kTestTypes = {"isotropic", "oedometer", "triaxial",
                                             "undrained-triaxial", "strain-path"};
const std::vector<std::string> kConventions = {"initial-stress", "zero-pressure"};
const std::vector<std::string> kIgsInitial = {"compression", "zero", "first-increment"};
// Keys [defaults] may set for every test.
const std::vector<std::string> kDefaultKeys = {"set", "igs", "e0", "e0_at", "igs_initial"};

// Library validation of a test names its keys as the case file does, except these.
const KeyMap kTestKeys = {{"sigma_v_targets_kPa", "sigma_v_kPa"}};

// A key of a test is read from the [[test]] table when it is there, else from [defaults].
struct Layers {
  TableReader& test;
  TableReader* defaults;
  TableReader& at(std::string_view key) {
    if (test.contains(key)) return test;
    if (defaults != nullptr && defaults->contains(key)) return *defaults;
    return test;
  }
};

// Compression-positive components (11, 22, 33[, 23, 13, 12]) to a tension-positive Mandel
// vector (tensor shear components, scaled by sqrt2).
Vec6 mandel_from_compression_positive(const std::vector<double>& c, double scale) {
  Vec6 v = Vec6::Zero();
  for (std::size_t i = 0; i < c.size(); ++i)
    v[static_cast<Eigen::Index>(i)] = -c[i] * scale * (i < 3 ? 1.0 : kSqrt2);
  return v;
}

// igs_initial: a name (compression, zero, first-increment) or the tensor delta as 3 or 6
// components, compression positive like the strains of a strain path.
void read_igs_initial(TableReader& t, InitialCondition& initial) {
  const toml::node* node = t.node("igs_initial");
  if (node != nullptr && node->is_array()) {
    const std::vector<double> d = t.number_array("igs_initial", NumberRange::open(-1.0, 1.0), 3, 6);
    if (d.size() != 3 && d.size() != 6)
      throw t.error("igs_initial",
                    "wrong size: give 3 (d11, d22, d33) or 6 (..., d23, d13, d12) components");
    initial.igs = InitialCondition::Igs::tensor;
    initial.igs_tensor = mandel_from_compression_positive(d, 1.0);
    return;
  }
  const std::string name = t.optional_choice("igs_initial", kIgsInitial).value_or("compression");
  initial.igs = name == "zero"              ? InitialCondition::Igs::zero
                : name == "first-increment" ? InitialCondition::Igs::first_increment
                                            : InitialCondition::Igs::compression;
}

// The keys of each test type (besides the common ones).
std::vector<std::string> programme_keys(const std::string& type) {
  if (type == "isotropic") return {"p0_kPa", "p_end_kPa", "steps"};
  if (type == "oedometer") return {"sigma_v0_kPa", "K0", "sigma_v_kPa", "steps_per_segment"};
  if (type == "triaxial") return {"sigma3_kPa", "axial_strain", "steps"};
  if (type == "undrained-triaxial") return {"p0_kPa", "axial_strain", "steps"};
  return {"initial_stress_kPa", "segments"};
}

// `jaky_K0`: the default K0 = 1 - sin(phi_c) of a hypoplastic material (none for other models).
ElementTest read_test_programme(TableReader& t, const std::string& type,
                                std::optional<double> jaky_K0) {
  const NumberRange positive = NumberRange::positive();
  const NumberRange strain = NumberRange::open(0.0, 1.0);
  if (type == "isotropic") {
    IsotropicCompressionTest x;
    x.p0 = t.number("p0_kPa", positive) * kKPa;
    x.p_end = t.number("p_end_kPa", positive) * kKPa;
    x.steps = t.integer_or("steps", x.steps, 1, kMaxSteps);
    return x;
  }
  if (type == "oedometer") {
    OedometerTest x;
    x.sigma_v0 = t.number("sigma_v0_kPa", positive) * kKPa;
    const NumberRange k0_range = NumberRange::left_open(0.0, 5.0);
    x.K0 = jaky_K0 ? t.number_or("K0", *jaky_K0, k0_range) : t.number("K0", k0_range);
    x.sigma_v_targets = t.number_array("sigma_v_kPa", positive, 1, 1000, true);
    for (double& s : x.sigma_v_targets) s *= kKPa;
    x.steps_per_segment = t.integer_or("steps_per_segment", x.steps_per_segment, 1, kMaxSteps);
    return x;
  }
  if (type == "triaxial") {
    DrainedTriaxialTest x;
    x.sigma3 = t.number("sigma3_kPa", positive) * kKPa;
    x.axial_strain = t.number("axial_strain", strain);
    x.steps = t.integer_or("steps", x.steps, 1, kMaxSteps);
    return x;
  }
  if (type == "undrained-triaxial") {
    UndrainedTriaxialTest x;
    x.p0 = t.number("p0_kPa", positive) * kKPa;
    x.axial_strain = t.number("axial_strain", strain);
    x.steps = t.integer_or("steps", x.steps, 1, kMaxSteps);
    return x;
  }
  // strain-path
  StrainPathTest x;
  const std::vector<double> stress = t.number_array("initial_stress_kPa", NumberRange::any(), 3, 6);
  if (stress.size() != 3 && stress.size() != 6)
    throw t.error("initial_stress_kPa",
                  "wrong size: give 3 (s11, s22, s33) or 6 (..., s23, s13, s12) components");
  x.initial_stress = mandel_from_compression_positive(stress, kKPa);
  if (!(mean_stress(x.initial_stress) > 0.0))
    throw t.error("initial_stress_kPa",
                  "not allowed: must be a compressive state, mean stress > 0 (compression "
                  "positive)");
  std::vector<TableReader> segments = t.tables("segments");
  if (segments.empty())
    throw t.missing("segments",
                    "an array of at least one {strain = [e11, e22, e33(, e23, e13, e12)], "
                    "steps = N} is required");
  for (TableReader& s : segments) {
    s.declare({"strain", "steps"});
    const std::vector<double> e = s.number_array("strain", NumberRange::open(-1.0, 1.0), 3, 6);
    if (e.size() != 3 && e.size() != 6)
      throw s.error("strain",
                    "wrong size: give 3 (e11, e22, e33) or 6 (..., e23, e13, e12) components");
    StrainPathTest::Segment segment;
    segment.strain = mandel_from_compression_positive(e, 1.0);
    segment.steps = s.integer("steps", 1, kMaxSteps);
    s.check_no_unknown_keys();
    x.segments.push_back(segment);
  }
  return x;
}

ElementCase read_test(TableReader& t, TableReader* defaults, const MaterialCatalog& catalog) {
  Layers layers{t, defaults};
  ElementCase c;
  c.source = fmt::format("{}:{}", t.file(), t.line());
  c.name = t.string("name");
  if (const std::string problem = test_name_problem(c.name); !problem.empty())
    throw t.error("name", problem);
  const std::string type = t.choice("type", kTestTypes);
  t.declare({"note", "set", "igs", "igs_initial", "e0", "e0_at"});
  t.declare(programme_keys(type));
  c.note = t.optional_string("note").value_or("");

  // Material.
  TableReader& set_reader = layers.at("set");
  const std::string set = set_reader.string("set");
  const MaterialSpec* material = catalog.find(set);
  if (material == nullptr)
    throw set_reader.error(
        "set", fmt::format("unknown: must be a [[material]] name or a built-in set, one of {}",
                           fmt::join(catalog.names(), ", ")));
  c.material = *material;
  c.integrator = catalog.integrator();
  const bool hypoplastic = material->is_hypoplastic();

  // Intergranular strain: the test's own igs, else the material's, else [defaults].
  if (hypoplastic) {
    if (t.contains("igs"))
      c.igs = read_igs(t, "igs");
    else if (material->hypoplastic_material().igs)
      c.igs = material->hypoplastic_material().igs;
    else if (defaults != nullptr && defaults->contains("igs"))
      c.igs = read_igs(*defaults, "igs");
    else
      throw t.missing("igs", fmt::format("the hypoplastic model needs igs = one of {} or "
                                         "an inline table, in the test, its [[material]] or "
                                         "[defaults]",
                                         fmt::join(igs_choice_names(), ", ")));
    read_igs_initial(layers.at("igs_initial"), c.initial);
  } else {
    for (const char* key : {"igs", "igs_initial"})
      if (t.contains(key))
        throw t.error(key, fmt::format("not allowed: the intergranular strain belongs to the "
                                       "hypoplastic model, and set \"{}\" is {}",
                                       set, material->model));
  }

  // Initial void ratio and its convention: required for every model (all of them carry e).
  TableReader& e0_reader = layers.at("e0");
  if (!e0_reader.contains("e0"))
    throw t.missing("e0", "the initial void ratio e0 (> 0) is required");
  c.initial.e0 = e0_reader.number("e0", NumberRange::positive());
  TableReader& at_reader = layers.at("e0_at");
  if (!at_reader.contains("e0_at"))
    throw t.missing("e0_at",
                    "say which state e0 refers to: e0_at = \"initial-stress\" (e0 is the void "
                    "ratio at the test's initial stress) or \"zero-pressure\" (e0 is scaled from "
                    "p = 0 to the initial stress by Bauer's law, as the UMAT does)");
  c.initial.e0_at = parse_void_ratio_convention(at_reader.choice("e0_at", kConventions), "e0_at");
  if (!hypoplastic && c.initial.e0_at == VoidRatioConvention::at_zero_pressure)
    throw at_reader.error("e0_at", fmt::format("not allowed for set \"{}\" ({}): scaling from "
                                               "zero pressure needs the hypoplastic h_s and n; "
                                               "use \"initial-stress\"",
                                               set, material->model));

  // The loading programme.
  std::optional<double> jaky_K0;
  if (hypoplastic) jaky_K0 = 1.0 - std::sin(material->hypoplastic().phi_c_deg * kPi / 180.0);
  c.test = read_test_programme(t, type, jaky_K0);
  try {
    validate(c.test);
  } catch (const InvalidValue& e) {
    throw t.error_from(e, kTestKeys);
  }
  t.check_no_unknown_keys();

  try {
    c.model = make_model(c.material, c.igs, c.integrator);
    if (c.initial.igs == InitialCondition::Igs::tensor)
      (void)initial_state(*c.model, initial_stress_of(c.test), c.initial);  // ||delta|| <= R
  } catch (const InvalidValue& e) {
    throw layers.at("igs_initial").error_from(e);
  }
  if (const std::string problem = initial_void_ratio_problem(c); !problem.empty())
    throw e0_reader.error("e0", problem);
  return c;
}

std::string lower(std::string_view s) {
  std::string r(s);
  for (char& ch : r) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return r;
}

}  // namespace

const std::vector<std::string>& element_test_types() {
  return kTestTypes;
}

std::vector<std::string> element_test_programme_keys(const std::string& type) {
  return programme_keys(type);
}

ElementTest read_element_test_programme(TableReader& table, const std::string& type,
                                        std::optional<double> jaky_K0) {
  ElementTest test = read_test_programme(table, type, jaky_K0);
  try {
    validate(test);
  } catch (const InvalidValue& e) {
    throw table.error_from(e, kTestKeys);
  }
  return test;
}

void read_element_initial_igs(TableReader& table, InitialCondition& initial) {
  read_igs_initial(table, initial);
}

std::string test_name_problem(std::string_view name) {
  const bool characters_ok = std::all_of(name.begin(), name.end(), [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_' || ch == '.';
  });
  if (name.empty() || name.size() > 100 || !characters_ok ||
      !std::isalnum(static_cast<unsigned char>(name.front())))
    return "not allowed: a test name names its output files, so it must be 1 to 100 letters, "
           "digits, '-', '_' or '.', starting with a letter or digit";
  const std::string l = lower(name);
  if (l == "summary" || l == "case")
    return "not allowed: \"summary\" and \"case\" name the case's own output files";
  return "";
}

Vec6 initial_stress_of(const ElementTest& test) {
  struct Visitor {
    Vec6 operator()(const IsotropicCompressionTest& t) const { return -t.p0 * identity6(); }
    Vec6 operator()(const OedometerTest& t) const {
      return -diagonal6(t.sigma_v0, t.K0 * t.sigma_v0, t.K0 * t.sigma_v0);
    }
    Vec6 operator()(const DrainedTriaxialTest& t) const { return -t.sigma3 * identity6(); }
    Vec6 operator()(const UndrainedTriaxialTest& t) const { return -t.p0 * identity6(); }
    Vec6 operator()(const StrainPathTest& t) const { return t.initial_stress; }
  };
  return std::visit(Visitor{}, test);
}

std::string initial_void_ratio_problem(const ElementCase& c) {
  if (!c.material.is_hypoplastic()) return "";
  const double p0 = mean_stress(initial_stress_of(c.test));
  const double e = initial_void_ratio(c.material.hypoplastic(), c.initial.e0, c.initial.e0_at, p0);
  const LimitVoidRatios limits = limit_void_ratios(c.material.hypoplastic(), p0);
  if (e >= limits.e_d && e <= limits.e_i) return "";
  return fmt::format(
      "out of range: with e0_at = \"{}\" the void ratio at the initial mean stress p0 = {} kPa "
      "is e = {:.4f}, outside the model's band [e_d, e_i] = [{:.4f}, {:.4f}] of set \"{}\" at "
      "that stress",
      to_string(c.initial.e0_at), format_value(p0 / kKPa), e, limits.e_d, limits.e_i,
      c.material.name);
}

ElementCaseFile parse_element_case(std::string text, const std::string& source_name) {
  const toml::table document = parse_toml_text(text, source_name);
  TableReader root(document, source_name, "");
  ElementCaseFile file;
  file.source = source_name;
  file.title = root.optional_string("title").value_or("");

  MaterialCatalog catalog;
  catalog.read(root);

  std::optional<TableReader> defaults = root.table("defaults");
  if (defaults) {
    for (const auto& key : kDefaultKeys) defaults->contains(key);
    defaults->check_no_unknown_keys();
  }

  std::vector<TableReader> tests = root.tables("test");
  root.check_no_unknown_keys();
  if (tests.empty())
    throw InputError(source_name, 0, "test", "",
                     "missing: a case file needs at least one [[test]] table");

  std::map<std::string, std::string> first_use;  // lower-case name -> where it was first used
  for (TableReader& t : tests) {
    ElementCase c = read_test(t, defaults ? &*defaults : nullptr, catalog);
    // File names may be case-insensitive, so names must differ in more than case.
    const auto [it, inserted] = first_use.emplace(lower(c.name), c.source);
    if (!inserted)
      throw t.error("name", fmt::format("duplicate: a test of this name (ignoring case) is "
                                        "already defined at {}; names must be unique because "
                                        "they name the output files",
                                        it->second));
    file.tests.push_back(std::move(c));
  }
  file.text = std::move(text);
  return file;
}

ElementCaseFile read_element_case_file(const std::filesystem::path& path) {
  return parse_element_case(read_case_text(path), path.string());
}

std::string_view builtin_element_case_text() {
  return {reinterpret_cast<const char*>(generated::kDefaultElementCase),
          sizeof(generated::kDefaultElementCase)};
}

ElementCaseFile builtin_element_case() {
  return parse_element_case(std::string(builtin_element_case_text()), kBuiltinElementCaseName);
}

}  // namespace pilempm
