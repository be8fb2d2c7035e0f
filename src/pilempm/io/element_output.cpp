#include "pilempm/io/element_output.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

#include "pilempm/io/text_escaping.hpp"

#include "pilempm/io/text_escaping.hpp"

namespace pilempm {

namespace fs = std::filesystem;

namespace {

constexpr double kKPa = 1.0e3;
constexpr double kMPa = 1.0e6;

std::string system_error_text() {
  return std::strerror(errno);
}

// Writes all of `content` to a new file and syncs it; false with errno set on failure.
bool write_and_sync(const fs::path& path, std::string_view content) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  const char* data = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int saved = errno;
      ::close(fd);
      errno = saved;
      return false;
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const int saved = errno;
    ::close(fd);
    errno = saved;
    return false;
  }
  return ::close(fd) == 0;
}

// A number for CSV and JSON: shortest round-trip form; JSON has no NaN or infinity.
std::string number_text(double value, bool json = false) {
  if (!std::isfinite(value)) return json ? "null" : (std::isnan(value) ? "nan" : "inf");
  return fmt::format("{:.10g}", value + 0.0);  // + 0.0: no "-0" for a negated zero
}

// A small writer of indented JSON objects.
class JsonWriter {
 public:
  JsonWriter() { open("", '{'); }
  JsonWriter& object(std::string_view key) { return open(key, '{'); }
  JsonWriter& end() {
    const char close = closers_.back();
    closers_.pop_back();
    first_.pop_back();
    out_ += fmt::format("\n{:{}}{}", "", 2 * closers_.size(), close);
    return *this;
  }
  JsonWriter& number(std::string_view key, double value) {
    return raw(key, number_text(value, true));
  }
  JsonWriter& integer(std::string_view key, long value) { return raw(key, std::to_string(value)); }
  JsonWriter& boolean(std::string_view key, bool value) {
    return raw(key, value ? "true" : "false");
  }
  JsonWriter& string(std::string_view key, std::string_view value) {
    return raw(key, json_quote(value));
  }
  JsonWriter& numbers(std::string_view key, const std::vector<double>& values) {
    std::string list = "[";
    for (std::size_t i = 0; i < values.size(); ++i)
      list.append(i ? ", " : "").append(number_text(values[i], true));
    return raw(key, list + "]");
  }
  std::string finish() {
    while (!closers_.empty()) end();
    return out_ + "\n";
  }

 private:
  JsonWriter& open(std::string_view key, char opener) {
    if (!closers_.empty()) prefix(key);
    out_ += opener;
    closers_.push_back(opener == '{' ? '}' : ']');
    first_.push_back(true);
    return *this;
  }
  void prefix(std::string_view key) {
    out_ += first_.back() ? "\n" : ",\n";
    first_.back() = false;
    out_ += fmt::format("{:{}}", "", 2 * closers_.size());
    if (!key.empty()) out_ += json_quote(key) + ": ";
  }
  JsonWriter& raw(std::string_view key, const std::string& text) {
    prefix(key);
    out_ += text;
    return *this;
  }
  std::string out_;
  std::vector<char> closers_;
  std::vector<bool> first_;
};

std::string igs_name(const ElementCase& c) {
  if (c.material.kind != ModelKind::hypoplastic) return "-";
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

void write_material(JsonWriter& j, const ElementCase& c) {
  const MaterialSpec& m = c.material;
  j.object("material");
  j.string("name", m.name).string("model", to_string(m.kind)).string("origin", m.origin);
  if (!m.base.empty()) j.string("base", m.base);
  switch (m.kind) {
    case ModelKind::hypoplastic: {
      const HypoplasticParameters& p = m.hypoplastic;
      j.number("phi_c_deg", p.phi_c_deg)
          .number("h_s_MPa", p.h_s / kMPa)
          .number("n", p.n)
          .number("e_d0", p.e_d0)
          .number("e_c0", p.e_c0)
          .number("e_i0", p.e_i0)
          .number("alpha", p.alpha)
          .number("beta", p.beta);
      if (p.stress_dependence.enabled()) {
        const StressDependence& d = p.stress_dependence;
        j.object("stress_dependence")
            .boolean("alpha", d.alpha_varies)
            .number("alpha_low", d.alpha_low)
            .number("alpha_high", d.alpha_high)
            .number("p_low_kPa", d.p_low / kKPa)
            .number("p_high_kPa", d.p_high / kKPa)
            .boolean("rohe_void_ratios", d.rohe_void_ratios)
            .end();
      }
      j.object("igs").string("name", igs_name(c));
      if (c.igs && c.igs->parameters.enabled()) {
        const IntergranularStrainParameters& g = c.igs->parameters;
        j.number("m_R", g.m_R)
            .number("m_T", g.m_T)
            .number("R", g.R)
            .number("beta_r", g.beta_r)
            .number("chi", g.chi);
      }
      j.end();
      j.object("integrator")
          .string("scheme", to_string(c.integrator.scheme))
          .number("tolerance", c.integrator.tolerance)
          .number("min_mean_stress_Pa", c.integrator.min_mean_stress)
          .integer("fixed_substeps", c.integrator.fixed_substeps)
          .end();
      break;
    }
    case ModelKind::mohr_coulomb: {
      const MohrCoulombParameters& p = m.mohr_coulomb;
      j.number("young_modulus_MPa", p.young_modulus / kMPa)
          .number("poisson_ratio", p.poisson_ratio)
          .number("cohesion_kPa", p.cohesion / kKPa)
          .number("friction_angle_deg", p.friction_angle_deg)
          .number("dilatancy_angle_deg", p.dilatancy_angle_deg)
          .number("tension_cutoff_kPa", p.tension_cutoff / kKPa);  // null: no cut-off
      break;
    }
    case ModelKind::linear_elastic:
      j.number("young_modulus_MPa", m.elastic.young_modulus / kMPa)
          .number("poisson_ratio", m.elastic.poisson_ratio);
      break;
  }
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

std::string fixed(double value, int digits) {
  if (!std::isfinite(value)) return "-";
  return fmt::format("{:.{}f}", value, digits);
}

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
         return r.ok ? fixed(r.summary.initial_void_ratio, 4) : std::string("-");
       }},
      {"p0 kPa",
       [](const ElementRunRecord& r) {
         return fmt::format("{:.6g}", mean_stress(initial_stress_of(r.test->test)) / kKPa);
       }},
      {"peak q kPa",
       [](const ElementRunRecord& r) {
         return shows_peak(r) ? fmt::format("{:.6g}{}", r.summary.peak_q / kKPa,
                                            r.summary.peak_at_end ? " (end)" : "")
                              : std::string("-");
       }},
      {"phi peak deg",
       [](const ElementRunRecord& r) {
         return shows_peak(r) ? fixed(r.summary.phi_at_peak_deg, 2) : std::string("-");
       }},
      {"psi peak deg",
       [](const ElementRunRecord& r) {
         return shows_peak(r) && std::holds_alternative<DrainedTriaxialTest>(r.test->test)
                    ? fixed(r.summary.psi_at_peak_deg, 2)
                    : std::string("-");
       }},
      {"e end",
       [](const ElementRunRecord& r) {
         return r.ok ? fixed(r.summary.final.void_ratio, 4) : std::string("-");
       }},
      {"sigma_a end kPa",
       [](const ElementRunRecord& r) {
         return r.ok ? fmt::format("{:.6g}", r.summary.final.axial_stress / kKPa)
                     : std::string("-");
       }},
      {"time s", [](const ElementRunRecord& r) { return fixed(r.seconds, 2); }},
      {"status",
       [](const ElementRunRecord& r) {
         return r.ok ? std::string("ok") : std::string("FAILED: ") + r.error;
       }},
  };
  return columns;
}

}  // namespace

void write_file_atomically(const fs::path& path, std::string_view content) {
  fs::path tmp = path;
  tmp += ".tmp";
  if (!write_and_sync(tmp, content)) {
    const std::string why = system_error_text();
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw Error(fmt::format("cannot write {}: {}", tmp.string(), why));
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw Error(
        fmt::format("cannot rename {} to {}: {}", tmp.string(), path.string(), ec.message()));
  }
}

void prepare_output_directory(const fs::path& directory) {
  const fs::path dir = directory.empty() ? fs::path(".") : directory;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw Error(
        fmt::format("output folder {}: cannot create it{}", dir.string(),
                    ec ? ": " + ec.message() : std::string(" (a file of that name exists)")));
  const fs::path probe = dir / fmt::format(".pilempm-write-check-{}", ::getpid());
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0)
    throw Error(
        fmt::format("output folder {} is not writable: {}", dir.string(), system_error_text()));
  ::close(fd);
  fs::remove(probe, ec);
}

void check_output_file(const fs::path& file) {
  std::error_code ec;
  if (fs::is_directory(file, ec))
    throw Error(fmt::format("output file {} is a folder", file.string()));
  prepare_output_directory(file.parent_path());
}

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
  if (c.material.kind == ModelKind::hypoplastic)
    j.string("igs_initial", std::string(to_string(c.initial.igs)));
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
        std::string(to_string(c.material.kind)),
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
    f.push_back(fmt::format("{:.3f}", r.seconds));
    f.push_back(r.ok ? "ok" : "failed: " + r.error);
    f.push_back(r.curve_file.empty() ? "" : r.curve_file.filename().string());
    for (std::size_t i = 0; i < f.size(); ++i) {
      if (i > 0) out += ',';
      out += csv_field(f[i]);
    }
    out += '\n';
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
      "actually used. phi and psi at the peak of q (\"(end)\": q still rising at the end).\n\n|";
  for (const Column& c : columns) out += " " + c.header + " |";
  out += "\n|";
  for (std::size_t i = 0; i < columns.size(); ++i) out += i < 4 ? " --- |" : " ---: |";
  out += '\n';
  for (const ElementRunRecord& r : records) {
    out += '|';
    for (const Column& c : columns) {
      std::string cell = c.cell(r);
      std::string escaped;
      for (char ch : cell) {
        if (ch == '|') escaped += '\\';
        escaped += ch == '\n' ? ' ' : ch;
      }
      out += " " + escaped + " |";
    }
    out += '\n';
  }
  return out;
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
