#include "pilempm/io/element_output.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "pilempm/io/output/format.hpp"
#include "pilempm/io/output/json_writer.hpp"

namespace pilempm {

namespace fs = std::filesystem;

namespace {

constexpr double kKPa = 1.0e3;
constexpr double kMPa = 1.0e6;

// A number of the curve CSV and of the summaries: kCurveDigits significant digits.
std::string number_text(double value) {
  return csv_number(value, kCurveDigits);
}

std::string igs_name(const ElementCase& c) {
  if (!c.material.is_hypoplastic()) return "-";
  return c.igs ? c.igs->name : "none";
}

void write_programme(JsonWriter& j, const ElementTest& test) {
  struct Visitor {
    JsonWriter& j;
    void operator()(const IsotropicCompressionTest& t) const {
      j.number("p0_kPa", t.p0 / kKPa).number("p_end_kPa", t.p_end / kKPa).integer("steps", t.steps);
    }
    void operator()(const OedometerTest& t) const {
      std::vector<double> targets;
      for (double s : t.sigma_v_targets) targets.push_back(s / kKPa);
      j.number("sigma_v0_kPa", t.sigma_v0 / kKPa)
          .number("K0", t.K0)
          .numbers("sigma_v_kPa", targets)
          .integer("steps_per_segment", t.steps_per_segment);
    }
    void operator()(const DrainedTriaxialTest& t) const {
      j.number("sigma3_kPa", t.sigma3 / kKPa)
          .number("axial_strain", t.axial_strain)
          .integer("steps", t.steps);
    }
    void operator()(const UndrainedTriaxialTest& t) const {
      j.number("p0_kPa", t.p0 / kKPa)
          .number("axial_strain", t.axial_strain)
          .integer("steps", t.steps);
    }
    void operator()(const StrainPathTest& t) const {
      const auto compression_positive = [](const Vec6& v, double scale) {
        std::vector<double> c;
        for (int i = 0; i < 6; ++i) c.push_back(-v[i] / scale / (i < 3 ? 1.0 : kSqrt2));
        return c;
      };
      j.numbers("initial_stress_kPa", compression_positive(t.initial_stress, kKPa));
      for (std::size_t i = 0; i < t.segments.size(); ++i) {
        j.object(fmt::format("segment_{}", i + 1));
        j.numbers("strain", compression_positive(t.segments[i].strain, 1.0))
            .integer("steps", t.segments[i].steps);
        j.end();
      }
    }
  };
  std::visit(Visitor{j}, test);
}

// A model's description of its parameters, as JSON keys of the open object.
class JsonParameterSink final : public ParameterSink {
 public:
  explicit JsonParameterSink(JsonWriter& j) : j_(j) {}
  void number(std::string_view key, double value) override { j_.number(key, value); }
  void integer(std::string_view key, long value) override { j_.integer(key, value); }
  void text(std::string_view key, std::string_view value) override { j_.string(key, value); }
  void boolean(std::string_view key, bool value) override { j_.boolean(key, value); }
  void begin_group(std::string_view key) override { j_.object(key); }
  void end_group() override { j_.end(); }

 private:
  JsonWriter& j_;
};

void write_material(JsonWriter& j, const ElementCase& c) {
  const MaterialSpec& m = c.material;
  j.object("material");
  j.string("name", m.name).string("model", m.model).string("origin", m.origin);
  JsonParameterSink sink(j);
  const MaterialSpec effective = with_igs(m, c.igs);  // the test's intergranular strain
  model_registry().at(m.model).describe(*effective.parameters, c.integrator, sink);
  j.end();
}

void write_point(JsonWriter& j, std::string_view key, const CurvePoint& c) {
  j.object(key)
      .number("axial_strain_pct", 100.0 * c.axial_strain)
      .number("radial_strain_pct", 100.0 * c.radial_strain)
      .number("volumetric_strain_pct", 100.0 * c.volumetric_strain)
      .number("sigma_a_kPa", c.axial_stress / kKPa)
      .number("sigma_r_kPa", c.radial_stress / kKPa)
      .number("sigma_l_kPa", c.lateral_stress / kKPa)
      .number("p_kPa", c.p / kKPa)
      .number("q_kPa", c.q / kKPa)
      .number("void_ratio", c.void_ratio)
      .number("phi_mob_deg", c.phi_mobilised_deg)
      .number("igs_rho", c.igs_ratio)
      .end();
}

struct Column {
  std::string header;
  std::string (*cell)(const ElementRunRecord&);
};

bool shows_peak(const ElementRunRecord& r) {
  return r.ok && (std::holds_alternative<DrainedTriaxialTest>(r.test->test) ||
                  std::holds_alternative<UndrainedTriaxialTest>(r.test->test) ||
                  std::holds_alternative<StrainPathTest>(r.test->test));
}

std::string e0_text(const ElementRunRecord& r) {
  return fmt::format("{} ({})", format_value(r.test->initial.e0),
                     r.test->initial.e0_at == VoidRatioConvention::at_zero_pressure ? "p=0" : "p0");
}

// The columns a person reads: the terminal table and the Markdown table.
const std::vector<Column>& human_columns() {
  static const std::vector<Column> columns = {
      {"test", [](const ElementRunRecord& r) { return r.test->name; }},
      {"type", [](const ElementRunRecord& r) { return test_type_name(r.test->test); }},
      {"set", [](const ElementRunRecord& r) { return r.test->material.name; }},
      {"IGS", [](const ElementRunRecord& r) { return igs_name(*r.test); }},
      {"e0 (at)", e0_text},
      {"e start",
       [](const ElementRunRecord& r) {
         return r.ok ? fixed_number(r.summary.initial_void_ratio, 4) : std::string("-");
       }},
      {"p0 kPa",
       [](const ElementRunRecord& r) {
         return shown_number(mean_stress(initial_stress_of(r.test->test)) / kKPa, "{:.6g}");
       }},
      {"peak q kPa",
       [](const ElementRunRecord& r) {
         return shows_peak(r) ? shown_number(r.summary.peak_q / kKPa, "{:.6g}") +
                                    (r.summary.peak_at_end ? " (end)" : "")
                              : std::string("-");
       }},
      {"phi peak deg",
       [](const ElementRunRecord& r) {
         return shows_peak(r) ? fixed_number(r.summary.phi_at_peak_deg, 2) : std::string("-");
       }},
      {"psi peak deg",
       [](const ElementRunRecord& r) {
         return shows_peak(r) && std::holds_alternative<DrainedTriaxialTest>(r.test->test)
                    ? fixed_number(r.summary.psi_at_peak_deg, 2)
                    : std::string("-");
       }},
      {"e end",
       [](const ElementRunRecord& r) {
         return r.ok ? fixed_number(r.summary.final.void_ratio, 4) : std::string("-");
       }},
      {"sigma_a end kPa",
       [](const ElementRunRecord& r) {
         return r.ok ? shown_number(r.summary.final.axial_stress / kKPa, "{:.6g}")
                     : std::string("-");
       }},
      {"time s", [](const ElementRunRecord& r) { return fixed_number(r.seconds, 2); }},
      {"status",
       [](const ElementRunRecord& r) {
         return r.ok ? std::string("ok") : std::string("FAILED: ") + r.error;
       }},
  };
  return columns;
}

}  // namespace

const std::vector<std::string>& curve_columns() {
  static const std::vector<std::string> columns = {
      "increment",   "axial_strain_pct", "radial_strain_pct", "volumetric_strain_pct",
      "sigma_a_kPa", "sigma_r_kPa",      "sigma_l_kPa",       "p_kPa",
      "q_kPa",       "void_ratio",       "phi_mob_deg",       "igs_rho",
      "substeps"};
  return columns;
}

std::string curve_csv(const std::vector<CurvePoint>& curve) {
  std::string out =
      "# pilempm element test curve; compression positive (stresses and strains); strains in "
      "percent; a = axial (1), r = radial (2), l = lateral (3); q = sigma_a - sigma_r\n";
  for (std::size_t i = 0; i < curve_columns().size(); ++i) {
    if (i > 0) out += ',';
    out += curve_columns()[i];
  }
  out += '\n';
  out.reserve(out.size() + curve.size() * 160);
  for (std::size_t i = 0; i < curve.size(); ++i) {
    const CurvePoint& c = curve[i];
    out += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{}\n", i,
                       number_text(100.0 * c.axial_strain), number_text(100.0 * c.radial_strain),
                       number_text(100.0 * c.volumetric_strain), number_text(c.axial_stress / kKPa),
                       number_text(c.radial_stress / kKPa), number_text(c.lateral_stress / kKPa),
                       number_text(c.p / kKPa), number_text(c.q / kKPa), number_text(c.void_ratio),
                       number_text(c.phi_mobilised_deg), number_text(c.igs_ratio), c.substeps);
  }
  return out;
}

std::string summary_json(const ElementRunRecord& r) {
  const ElementCase& c = *r.test;
  const ElementSummary& s = r.summary;
  JsonWriter j;
  j.string("name", c.name)
      .string("type", test_type_name(c.test))
      .string("source", c.source)
      .string("sign_convention", "compression positive");
  if (!c.note.empty()) j.string("note", c.note);
  j.string("status", r.ok ? "ok" : "failed");
  if (!r.ok) j.string("error", r.error);
  write_material(j, c);
  j.object("initial");
  j.number("e0", c.initial.e0).string("e0_at", to_string(c.initial.e0_at));
  if (c.material.is_hypoplastic()) j.string("igs_initial", std::string(to_string(c.initial.igs)));
  if (r.ok) j.number("void_ratio", s.initial_void_ratio);
  j.number("p_kPa", mean_stress(initial_stress_of(c.test)) / kKPa);
  j.end();
  j.object("programme");
  write_programme(j, c.test);
  j.end();
  if (r.ok) {
    j.object("peak")
        .number("q_kPa", s.peak_q / kKPa)
        .number("axial_strain_pct", 100.0 * s.axial_strain_at_peak)
        .number("phi_mob_deg", s.phi_at_peak_deg)
        .number("dilatancy_ratio", s.dilatancy_ratio_at_peak)
        .number("psi_deg", s.psi_at_peak_deg)
        .boolean("peak_at_end", s.peak_at_end)
        .end();
    write_point(j, "final", s.final);
    j.object("integration")
        .integer("increments", s.increments)
        .integer("substeps", s.substeps)
        .integer("mean_stress_floor_hits", s.mean_stress_floor_hits)
        .number("max_void_ratio_excess", s.max_void_ratio_excess)
        .end();
  }
  j.number("run_time_s", r.seconds);
  if (!r.curve_file.empty()) j.string("curve_file", r.curve_file.filename().string());
  return j.finish();
}

std::string summary_table_csv(const std::vector<ElementRunRecord>& records) {
  std::string out =
      "name,type,set,model,igs,e0,e0_at,initial_void_ratio,initial_p_kPa,peak_q_kPa,"
      "axial_strain_at_peak_pct,phi_peak_deg,dilatancy_ratio_at_peak,psi_peak_deg,peak_at_end,"
      "final_axial_strain_pct,final_volumetric_strain_pct,final_sigma_a_kPa,final_sigma_r_kPa,"
      "final_p_kPa,final_q_kPa,final_void_ratio,increments,substeps,mean_stress_floor_hits,"
      "max_void_ratio_excess,run_time_s,status,curve_file\n";
  for (const ElementRunRecord& r : records) {
    const ElementCase& c = *r.test;
    const ElementSummary& s = r.summary;
    std::vector<std::string> f = {
        c.name,
        test_type_name(c.test),
        c.material.name,
        c.material.model,
        igs_name(c),
        number_text(c.initial.e0),
        std::string(to_string(c.initial.e0_at)),
    };
    const auto add = [&f, &r](double value) { f.push_back(r.ok ? number_text(value) : ""); };
    add(s.initial_void_ratio);
    f.push_back(number_text(mean_stress(initial_stress_of(c.test)) / kKPa));
    add(s.peak_q / kKPa);
    add(100.0 * s.axial_strain_at_peak);
    add(s.phi_at_peak_deg);
    add(s.dilatancy_ratio_at_peak);
    add(s.psi_at_peak_deg);
    f.push_back(r.ok ? (s.peak_at_end ? "true" : "false") : "");
    add(100.0 * s.final.axial_strain);
    add(100.0 * s.final.volumetric_strain);
    add(s.final.axial_stress / kKPa);
    add(s.final.radial_stress / kKPa);
    add(s.final.p / kKPa);
    add(s.final.q / kKPa);
    add(s.final.void_ratio);
    f.push_back(r.ok ? std::to_string(s.increments) : "");
    f.push_back(r.ok ? std::to_string(s.substeps) : "");
    f.push_back(r.ok ? std::to_string(s.mean_stress_floor_hits) : "");
    add(s.max_void_ratio_excess);
    f.push_back(fixed_number(r.seconds, 3));
    f.push_back(r.ok ? "ok" : "failed: " + r.error);
    f.push_back(r.curve_file.empty() ? "" : r.curve_file.filename().string());
    out += csv_row(f);
  }
  return out;
}

std::string summary_table_markdown(const std::vector<ElementRunRecord>& records,
                                   const std::string& title) {
  const auto& columns = human_columns();
  std::string out = fmt::format("# {}\n\n", title.empty() ? "Element tests" : title);
  out +=
      "Compression positive. e0 (at): the given initial void ratio and its convention, p0 = at "
      "the initial stress, p=0 = at zero pressure scaled by Bauer's law; e start: the void ratio "
      "actually used. phi and psi at the peak of q (\"(end)\": q still rising at the end).\n\n";
  std::vector<std::string> header;
  for (const Column& c : columns) header.push_back(c.header);
  std::vector<std::vector<std::string>> rows;
  for (const ElementRunRecord& r : records) {
    rows.emplace_back();
    for (const Column& c : columns) rows.back().push_back(c.cell(r));
  }
  return out + markdown_table(header, rows, 4);
}

std::string summary_table_text(const std::vector<ElementRunRecord>& records) {
  const auto& columns = human_columns();
  std::vector<std::vector<std::string>> cells;
  std::vector<std::size_t> width(columns.size());
  for (std::size_t i = 0; i < columns.size(); ++i) width[i] = columns[i].header.size();
  for (const ElementRunRecord& r : records) {
    std::vector<std::string> row;
    for (std::size_t i = 0; i < columns.size(); ++i) {
      row.push_back(columns[i].cell(r));
      if (i + 1 < columns.size()) width[i] = std::max(width[i], row.back().size());
    }
    cells.push_back(std::move(row));
  }
  const auto line = [&](const std::vector<std::string>& row) {
    std::string out;
    for (std::size_t i = 0; i < row.size(); ++i) {
      if (i + 1 == row.size())
        out += row[i];
      else if (i < 4)
        out += fmt::format("{:<{}}  ", row[i], width[i]);
      else
        out += fmt::format("{:>{}}  ", row[i], width[i]);
    }
    return out + "\n";
  };
  std::vector<std::string> header;
  for (const Column& c : columns) header.push_back(c.header);
  std::string out = line(header);
  for (const auto& row : cells) out += line(row);
  return out;
}

}  // namespace pilempm
