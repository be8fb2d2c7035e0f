// The `pilempm analytic ...` subcommands: tables of the analytical relations of docs/study.md §3
// (Bolton, Rohe, Bauer, Herle & Gudehus) on stdout, and optionally as CSV.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cli/commands.hpp"
#include "pilempm/analytic/bauer.hpp"
#include "pilempm/analytic/bolton.hpp"
#include "pilempm/analytic/herle_gudehus.hpp"
#include "pilempm/constitutive/hypoplastic/hypoplastic_parameters.hpp"
#include "pilempm/constitutive/hypoplastic/rohe_void_ratios.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/io/output/atomic_file.hpp"
#include "pilempm/io/output/format.hpp"
#include "pilempm/io/toml_reader.hpp"

namespace pilempm::cli {

namespace {

constexpr double kPascalPerKilopascal = 1.0e3;
constexpr double kPascalPerMegapascal = 1.0e6;

// ---- tables: aligned on stdout, full precision in CSV -----------------------------------------

/// One cell: how it is shown on the terminal and how it is written to CSV.
struct Cell {
  std::string shown;
  std::string csv;
};

Cell number(double value, int decimals) {
  return {fixed_number(value, decimals), csv_number(value)};
}
Cell input_value(double value) {
  return {format_value(value), csv_number(value)};
}
Cell text(std::string_view value) {
  return {std::string(value), std::string(value)};
}
Cell missing() {
  return {"-", ""};
}

class Table {
 public:
  explicit Table(std::vector<std::string> columns) : columns_(std::move(columns)) {}

  void add_row(std::vector<Cell> cells) { rows_.push_back(std::move(cells)); }

  /// Right-aligned columns separated by two spaces; the header holds the CSV column names.
  void print(std::FILE* stream) const {
    std::vector<std::size_t> widths;
    for (const auto& column : columns_) widths.push_back(column.size());
    for (const auto& row : rows_)
      for (std::size_t i = 0; i < row.size(); ++i)
        widths[i] = std::max(widths[i], row[i].shown.size());
    auto print_line = [&](auto&& cell_text) {
      std::string line;
      for (std::size_t i = 0; i < columns_.size(); ++i)
        line += fmt::format("{}{:>{}}", i == 0 ? "" : "  ", cell_text(i), widths[i]);
      fmt::print(stream, "{}\n", line);
    };
    print_line([&](std::size_t i) { return columns_[i]; });
    for (const auto& row : rows_) print_line([&](std::size_t i) { return row[i].shown; });
  }

  /// Atomically, every write checked (a full disk is an error naming the file).
  void write_csv(const std::string& path) const {
    std::string text = csv_row(columns_);
    for (const auto& row : rows_) {
      std::vector<std::string> values;
      for (const auto& cell : row) values.push_back(cell.csv);
      text += csv_row(values);
    }
    write_file_atomically(path, text);
  }

 private:
  std::vector<std::string> columns_;
  std::vector<std::vector<Cell>> rows_;
};

/// Writes the CSV first, so that a file that cannot be written fails before any output.
/// `description` comes before the table, as lines starting with '#'.
void emit(const std::string& description, const Table& table, const std::string& csv_path) {
  if (!csv_path.empty()) table.write_csv(csv_path);
  fmt::print("{}", description);
  table.print(stdout);
}

// ---- command-line values and their names ---------------------------------------------------

/// A library key and the command-line option it comes from, with the value as the user typed
/// it (in the option's unit).
struct OptionOrigin {
  OptionOrigin(std::string_view library_key, std::string_view option_name, double option_value)
      : key(library_key), option(option_name), value(format_value(option_value)) {}
  OptionOrigin(std::string_view library_key, std::string_view option_name, std::string option_value)
      : key(library_key), option(option_name), value(std::move(option_value)) {}
  std::string_view key;
  std::string_view option;
  std::string value;
};

/// Runs `body`; an InvalidValue about one of `origins`' keys is rethrown under the option's name
/// and with the value in the option's unit, so the message says what to change on the command
/// line ("--id (I_D) = 1.5 is not allowed: must be in [0, 1]").
template <class Body>
auto naming_options(const std::vector<OptionOrigin>& origins, Body&& body) {
  try {
    return body();
  } catch (const InvalidValue& error) {
    for (const auto& origin : origins)
      if (error.key() == origin.key)
        throw InvalidValue(fmt::format("{} ({})", origin.option, error.key()), origin.value,
                           error.allowed());
    throw;
  }
}

/// Pressures the relations are tabulated at by default [kPa].
const std::vector<double> kDefaultPressures_kPa = {10,   20,   50,   100,   200,   500,
                                                   1000, 2000, 5000, 10000, 20000, 30000};

CLI::Option* add_pressures(CLI::App* command, std::vector<double>& p_kPa, bool required) {
  auto* option =
      command->add_option("--p-kPa", p_kPa, "mean effective stresses [kPa], comma-separated")
          ->delimiter(',')
          ->check(sane_number());
  if (required) return option->required();
  return option->capture_default_str();
}

void add_csv(CLI::App* command, std::string& csv_path) {
  command->add_option("--csv", csv_path, "also write the table to this CSV file");
}

// ---- bolton -----------------------------------------------------------------------------------

void register_bolton(CLI::App& analytic) {
  struct Options {
    double relative_density = 0.0;
    double phi_c_deg = 0.0;
    std::vector<double> p_kPa;
    std::string csv_path;
  };
  auto options = std::make_shared<Options>();
  auto* command = analytic.add_subcommand(
      "bolton", "Bolton (1986) peak friction and dilatancy in triaxial compression");
  command->add_option("--id", options->relative_density, "relative density I_D [-], in [0, 1]")
      ->required()
      ->check(sane_number());
  command->add_option("--phi-c-deg", options->phi_c_deg, "critical-state friction angle [deg]")
      ->required()
      ->check(sane_number());
  add_pressures(command, options->p_kPa, true);
  add_csv(command, options->csv_path);
  command->callback([options] {
    Table table(
        {"p_kPa", "I_R", "phi_max_deg", "dilatancy_rate", "sin_psi_max", "psi_max_deg", "status"});
    std::vector<std::string> outside;
    for (const double p_kPa : options->p_kPa) {
      const BoltonResult result =
          naming_options({{"I_D", "--id", options->relative_density},
                          {"phi_c_deg", "--phi-c-deg", options->phi_c_deg},
                          {"p_Pa", "--p-kPa", p_kPa}},
                         [&] {
                           return bolton(options->relative_density, options->phi_c_deg,
                                         p_kPa * kPascalPerKilopascal);
                         });
      // Bolton (1986) fitted the relation for 0 <= I_R <= 4 (he takes 0 below and caps it at
      // 4 above); the table keeps the value as it is, as the study's does, and says so.
      const double index = result.relative_dilatancy_index;
      const char* status = index < 0.0   ? "I_R < 0: outside Bolton's range 0 <= I_R <= 4"
                           : index > 4.0 ? "I_R > 4: outside Bolton's range 0 <= I_R <= 4"
                                         : "ok";
      if (index < 0.0 || index > 4.0) outside.push_back(format_value(p_kPa));
      table.add_row({input_value(p_kPa), number(index, 3), number(result.phi_max_deg, 3),
                     number(result.dilatancy_rate, 3), number(result.sin_psi_max, 4),
                     number(result.psi_max_deg, 3), text(status)});
    }
    if (!outside.empty())
      fmt::print(stderr,
                 "warning: --p-kPa {}: outside the range of validity of Bolton's relation "
                 "(0 <= I_R <= 4; the values there are extrapolated)\n",
                 fmt::join(outside, ","));
    const std::string description = fmt::format(
        "# Bolton (1986), triaxial compression: I_D = {}, phi_c = {} deg; "
        "dilatancy_rate = (-d eps_v/d eps_1)_max, psi after Schanz & Vermeer (1996)\n",
        options->relative_density, options->phi_c_deg);
    emit(description, table, options->csv_path);
  });
}

// ---- rohe -------------------------------------------------------------------------------------

void register_rohe(CLI::App& analytic) {
  struct Options {
    std::vector<double> sigma_v_MPa = {0.1, 0.5, 1, 2, 5, 10, 20, 30};
    std::string csv_path;
  };
  auto options = std::make_shared<Options>();
  auto* command = analytic.add_subcommand(
      "rohe", "Rohe (2010) stress-dependent reference void ratios e_c0*, e_d0*, e_i0*");
  command
      ->add_option("--sigma-v-MPa", options->sigma_v_MPa,
                   "vertical effective stresses [MPa], comma-separated")
      ->delimiter(',')
      ->check(sane_number())
      ->capture_default_str();
  add_csv(command, options->csv_path);
  command->callback([options] {
    Table table({"sigma_v_MPa", "e_c0", "e_d0", "e_i0", "status"});
    std::vector<std::string> outside;
    for (const double sigma_v_MPa : options->sigma_v_MPa) {
      const RoheReferenceVoidRatios result = naming_options(
          {{"sigma_v_Pa", "--sigma-v-MPa", sigma_v_MPa}},
          [&] { return rohe_reference_void_ratios(sigma_v_MPa * kPascalPerMegapascal); });
      // The fit means something only while the void ratios are positive and ordered
      // e_d0 < e_c0 < e_i0 (beyond about 375 MPa e_d0 turns negative).
      const bool valid =
          result.e_d0 > 0.0 && result.e_d0 < result.e_c0 && result.e_c0 < result.e_i0;
      if (!valid) outside.push_back(format_value(sigma_v_MPa));
      table.add_row({input_value(sigma_v_MPa), number(result.e_c0, 4), number(result.e_d0, 4),
                     number(result.e_i0, 4), text(valid ? "ok" : "outside the range of validity")});
    }
    if (!outside.empty())
      fmt::print(stderr,
                 "warning: --sigma-v-MPa {}: outside the range of validity of Rohe's fit (it "
                 "gives e_d0 <= 0 or void ratios out of order there)\n",
                 fmt::join(outside, ","));
    const std::string description =
        "# Rohe (2010): reference void ratios against vertical effective stress\n";
    emit(description, table, options->csv_path);
  });
}

// ---- bauer ------------------------------------------------------------------------------------

/// A parameter of Bauer's law given on the command line, in the option's unit.
struct BauerOption {
  const char* name;                       ///< the option, e.g. "--h-s-MPa"
  const char* description;                ///< its help text
  const char* key;                        ///< the library's key in InvalidValue
  double HypoplasticParameters::*member;  ///< the parameter it sets
  double to_si;                           ///< factor from the option's unit to SI
  double value = 0.0;                     ///< bound to the option
  CLI::Option* option = nullptr;          ///< to ask whether it was given
};

void register_bauer(CLI::App& analytic) {
  struct Options {
    std::string set_name;
    CLI::Option* set = nullptr;
    std::array<BauerOption, 5> parameters = {{
        {"--h-s-MPa", "granular hardness h_s [MPa]", "h_s_Pa", &HypoplasticParameters::h_s,
         kPascalPerMegapascal},
        {"--n", "exponent n [-]", "n", &HypoplasticParameters::n, 1.0},
        {"--e-d0", "minimum void ratio at p = 0 [-]", "e_d0", &HypoplasticParameters::e_d0, 1.0},
        {"--e-c0", "critical void ratio at p = 0 [-]", "e_c0", &HypoplasticParameters::e_c0, 1.0},
        {"--e-i0", "maximum void ratio at p = 0 [-]", "e_i0", &HypoplasticParameters::e_i0, 1.0},
    }};
    std::vector<double> p_kPa = kDefaultPressures_kPa;
    std::string csv_path;
  };
  auto options = std::make_shared<Options>();
  auto* command = analytic.add_subcommand(
      "bauer", "Bauer (1996) compression law: limit void ratios e_d, e_c, e_i against p");
  options->set = command->add_option(
      "--set", options->set_name,
      fmt::format("named parameter set ({}); explicit parameters override its values",
                  fmt::join(hypoplastic_set_names(), ", ")));
  for (auto& parameter : options->parameters)
    parameter.option = command->add_option(parameter.name, parameter.value, parameter.description)
                           ->check(sane_number());
  add_pressures(command, options->p_kPa, false);
  add_csv(command, options->csv_path);
  command->callback([options] {
    const bool from_set = options->set->count() > 0;
    HypoplasticParameters parameters;
    if (from_set) {
      parameters = naming_options({{"set", "--set", options->set_name}},
                                  [&] { return hypoplastic_set(options->set_name); });
    } else {
      std::vector<std::string> absent;
      for (const auto& parameter : options->parameters)
        if (parameter.option->count() == 0) absent.emplace_back(parameter.name);
      if (!absent.empty())
        throw Error(fmt::format(
            "analytic bauer: give --set NAME, or all of --h-s-MPa, --n, --e-d0, --e-c0, --e-i0 "
            "(missing: {})",
            fmt::join(absent, ", ")));
    }
    std::vector<OptionOrigin> origins;
    bool overridden = false;
    for (const auto& parameter : options->parameters) {
      if (parameter.option->count() > 0) {
        parameters.*parameter.member = parameter.value * parameter.to_si;
        overridden = true;
      }
      origins.emplace_back(parameter.key, parameter.name,
                           parameters.*parameter.member / parameter.to_si);
    }

    Table table({"p_kPa", "e_d", "e_c", "e_i"});
    for (const double p_kPa : options->p_kPa) {
      const double p = p_kPa * kPascalPerKilopascal;
      origins.emplace_back("p_Pa", "--p-kPa", p_kPa);
      const std::vector<BauerRow> rows = naming_options(
          origins, [&] { return bauer_table(parameters, std::span<const double>(&p, 1)); });
      origins.pop_back();
      const LimitVoidRatios& limits = rows.front().limits;
      table.add_row({input_value(p_kPa), number(limits.e_d, 4), number(limits.e_c, 4),
                     number(limits.e_i, 4)});
    }
    const std::string description = fmt::format(
        "# Bauer (1996): e_x = e_x0 exp[-(3p/h_s)^n] with {}h_s = {} MPa, n = {}, "
        "e_d0 = {}, e_c0 = {}, e_i0 = {}\n",
        from_set ? fmt::format("set '{}'{}: ", options->set_name, overridden ? " with options" : "")
                 : "",
        parameters.h_s / kPascalPerMegapascal, parameters.n, parameters.e_d0, parameters.e_c0,
        parameters.e_i0);
    emit(description, table, options->csv_path);
  });
}

// ---- alpha ------------------------------------------------------------------------------------

void register_alpha(CLI::App& analytic) {
  struct Options {
    std::string set_name = "original";
    double e0 = 0.0;
    std::string convention = "initial-stress";
    std::vector<double> p_kPa = kDefaultPressures_kPa;
    std::string csv_path;
  };
  auto options = std::make_shared<Options>();
  auto* command = analytic.add_subcommand(
      "alpha",
      "Herle & Gudehus (1999) alpha against p in isotropic compression, with the peak angle "
      "from Bolton (1986) and the limit void ratios from Bauer's law");
  command
      ->add_option(
          "--set", options->set_name,
          fmt::format("named parameter set ({})", fmt::join(hypoplastic_set_names(), ", ")))
      ->capture_default_str();
  command->add_option("--e0", options->e0, "void ratio [-]")->required()->check(sane_number());
  command
      ->add_option("--e0-convention", options->convention,
                   "initial-stress: e = e0 at every p; zero-pressure: e = e0 exp[-(3p/h_s)^n]")
      ->capture_default_str();
  add_pressures(command, options->p_kPa, false);
  add_csv(command, options->csv_path);
  command->callback([options] {
    const HypoplasticParameters parameters = naming_options(
        {{"set", "--set", options->set_name}}, [&] { return hypoplastic_set(options->set_name); });
    const VoidRatioConvention convention =
        parse_void_ratio_convention(options->convention, "--e0-convention");
    Table table({"p_kPa", "e", "e_d", "e_c", "I_D", "phi_p_deg", "alpha", "status"});
    for (const double p_kPa : options->p_kPa) {
      const AlphaPoint point =
          naming_options({{"e0", "--e0", options->e0}, {"p_Pa", "--p-kPa", p_kPa}}, [&] {
            return alpha_isotropic(parameters, options->e0, convention,
                                   p_kPa * kPascalPerKilopascal);
          });
      table.add_row({input_value(p_kPa), number(point.void_ratio, 4), number(point.e_d, 4),
                     number(point.e_c, 4), number(point.relative_density, 4),
                     point.phi_p_deg ? number(*point.phi_p_deg, 3) : missing(),
                     point.alpha ? number(*point.alpha, 4) : missing(),
                     text(to_string(point.status))});
    }
    std::string description =
        fmt::format("# Herle & Gudehus (1999) alpha, set '{}' (phi_c = {} deg), e0 = {}: {}\n",
                    options->set_name, parameters.phi_c_deg, options->e0,
                    convention == VoidRatioConvention::at_initial_stress
                        ? "e = e0 at every pressure (--e0-convention initial-stress)"
                        : "e = e0 exp[-(3p/h_s)^n] (--e0-convention zero-pressure)");
    description += fmt::format(
        "# I_D = (e_c - e)/(e_c - e_d), phi_p from Bolton (1986) with this I_D; "
        "no alpha where phi_p <= phi_c or e is outside (e_d, e_c)\n");
    emit(description, table, options->csv_path);
  });
}

}  // namespace

void register_analytic_commands(CLI::App& app) {
  auto* analytic = app.add_subcommand(
      "analytic", "analytical relations: Bolton, Rohe, Bauer, Herle & Gudehus (docs/study.md §3)");
  analytic->require_subcommand(1);
  register_bolton(*analytic);
  register_rohe(*analytic);
  register_bauer(*analytic);
  register_alpha(*analytic);
}

}  // namespace pilempm::cli
