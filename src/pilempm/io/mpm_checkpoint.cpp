#include "pilempm/io/mpm_checkpoint.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <type_traits>
#include <utility>

#include "pilempm/core/error.hpp"
#include "pilempm/io/element_output.hpp"
#include "pilempm/io/output/atomic_file.hpp"

// File layout (version 2). Doubles are stored as native doubles and integers as native 32/64-bit
// integers, read back without conversion, so a round trip is bitwise.
//   /                  attributes: format, format_version, geometry ("plane-strain" or
//                      "axisymmetric"), grid_nx, grid_ny, particle_count, materials_count,
//                      body_count, threads (of the solver that wrote it, for information),
//                      analysis ("explicit" or "quasi-static": a restart continues the same)
//   /grid              x_nodes, y_nodes (for information; a restart checks the node counts)
//   /particles         one dataset per field, first dimension the particle: position (n, 2),
//                      velocity, mass (n), initial_volume, volume, initial_half_size,
//                      half_size, deformation_gradient (n, 2, 2; [p][row][column]),
//                      out_of_plane_stretch, material (int), external_force, stress (n, 6; Mandel),
//                      void_ratio
//   /particles/history one dataset (n, size) per history variable that a material's model
//                      declares (ConstitutiveModel::history_variables, by name, e.g.
//                      intergranular_strain (n, 6), plastic_shear_strain (n, 1)): a particle's
//                      value where its model declares the variable, zero elsewhere
//   /bodies/<k>        attributes kind ("polygon" or "pile"), part_count, friction,
//                      contact_distance; datasets vertices (m, 2), displacement (2), velocity (2),
//                      contact_force (2), contact_force_parts (parts, 2)
//   /run_state         attributes time, steps, max_wave_speed, wave_speed_step,
//                      max_particle_speed; /run_state/energies attributes kinetic, internal,
//                      external_work, damping, contact_work, absorbed; /run_state/scheme
//                      (the analysis's own arrays, mpm::SolverRunState::scheme_arrays, e.g. the
//                      quasi-static contact points) attribute count, datasets 0, 1, ... of
//                      doubles with attribute name
//   /run               attributes case_source, next_phase, phase_start; dataset initial_position
//                      (0 or n, 2); /run/records attribute count, datasets 0, 1, ...: one
//                      fixed-length string each with attributes name and length (bytes)
// Damage is detected (version 2): every dataset carries an attribute `checksum`, the 64-bit
// FNV-1a hash of its bytes as written, compared with the bytes read; and the file is written in
// HDF5's latest format, whose superblock, object headers (with the attributes) and link
// structures carry HDF5's own checksums, which the library verifies when it reads them.

namespace pilempm {

namespace fs = std::filesystem;
using mpm::Mat2;
using mpm::Particles;
using mpm::RigidBody;
using mpm::Vec2;

namespace {

constexpr const char* kFormat = "pilempm MPM checkpoint";

// What is stored must be everything there is: these break the build when a member is added to a
// structure the checkpoint copies, so that it gets stored too.
static_assert(sizeof(Particles) == 12 * sizeof(std::vector<double>),
              "a field was added to mpm::Particles: store it in the checkpoint");
struct StoredMaterialState {
  Vec6 stress;
  double void_ratio;
  std::array<double, kHistoryCapacity> history;  // as the models declare it
};
static_assert(sizeof(MaterialState) == sizeof(StoredMaterialState),
              "a member was added to MaterialState: store it in the checkpoint");
static_assert(sizeof(mpm::Energies) == 6 * sizeof(double),
              "a member was added to mpm::Energies: store it in the checkpoint");
struct StoredRunState {
  double time;
  long steps;
  mpm::Energies energies;
  double max_wave_speed;
  long wave_speed_step;
  double max_particle_speed;
  std::vector<mpm::RigidBodyForce> rigid_body_forces;
  std::vector<std::pair<std::string, std::vector<double>>> scheme_arrays;
};
static_assert(sizeof(mpm::SolverRunState) == sizeof(StoredRunState),
              "a member was added to mpm::SolverRunState: store it in the checkpoint");

// ---------------------------------------------------------------------------------------------
// HDF5 handles

// Owns one hid_t and closes it with the function its kind needs.
class Handle {
 public:
  using Close = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Close closer) : id_(id), close_(closer) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept
      : id_(std::exchange(other.id_, H5I_INVALID_HID)), close_(other.close_) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, H5I_INVALID_HID);
      close_ = other.close_;
    }
    return *this;
  }
  ~Handle() { reset(); }

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  /// Closes now; false when the close failed (for a file: its data may not all be written).
  bool close() {
    if (!valid()) return true;
    const herr_t status = close_(id_);
    id_ = H5I_INVALID_HID;
    return status >= 0;
  }

 private:
  void reset() {
    if (valid()) close_(id_);
    id_ = H5I_INVALID_HID;
  }
  hid_t id_ = H5I_INVALID_HID;
  Close close_ = nullptr;
};

// Turns off HDF5's printing of its error stack for the lifetime of the object (the errors are
// reported as exceptions instead) and restores what was set before.
class QuietHdf5Errors {
 public:
  QuietHdf5Errors() {
    H5Eget_auto2(H5E_DEFAULT, &function_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  QuietHdf5Errors(const QuietHdf5Errors&) = delete;
  QuietHdf5Errors& operator=(const QuietHdf5Errors&) = delete;
  ~QuietHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, function_, data_); }

 private:
  H5E_auto2_t function_ = nullptr;
  void* data_ = nullptr;
};

// The innermost message on HDF5's error stack (what went wrong at the bottom), or "".
std::string hdf5_error_text() {
  std::string text;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned n, const H5E_error2_t* error, void* data) -> herr_t {
        if (n == 0 && error->desc) *static_cast<std::string*>(data) = error->desc;
        return 0;
      },
      &text);
  return text;
}

// The 64-bit FNV-1a hash of `size` bytes (Fowler, Noll and Vo; offset basis and prime of the
// published 64-bit variant). Any change of one byte changes it.
std::uint64_t content_hash(const void* data, std::size_t size) {
  std::uint64_t hash = 14695981039346656037ULL;
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * 1099511628211ULL;
  return hash;
}

// The bytes of a dataset of `dims` in memory type `memory_type`.
std::size_t byte_count(hid_t memory_type, const std::vector<hsize_t>& dims) {
  return std::accumulate(dims.begin(), dims.end(), hsize_t{1}, std::multiplies<hsize_t>()) *
         H5Tget_size(memory_type);
}

// A fixed-length string type of `size` bytes (at least 1), padded with NULs.
Handle string_type(std::size_t size) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!type.valid() || H5Tset_size(type.get(), std::max<std::size_t>(size, 1)) < 0 ||
      H5Tset_strpad(type.get(), H5T_STR_NULLPAD) < 0 || H5Tset_cset(type.get(), H5T_CSET_UTF8) < 0)
    return {};
  return type;
}

// The geometry's name as case files spell it.
const char* geometry_name(mpm::Geometry geometry) {
  return geometry == mpm::Geometry::axisymmetric ? "axisymmetric" : "plane-strain";
}

// ---------------------------------------------------------------------------------------------
// Per-particle fields: one table for writing and reading, so that both see the same fields in the
// same layout.

void put(const Vec2& v, double* out) {
  out[0] = v.x();
  out[1] = v.y();
}
void take(Vec2& v, const double* in) {
  v = Vec2(in[0], in[1]);
}
void put(double v, double* out) {
  out[0] = v;
}
void take(double& v, const double* in) {
  v = in[0];
}
void put(const Vec6& v, double* out) {
  for (int k = 0; k < 6; ++k) out[k] = v[k];
}
void take(Vec6& v, const double* in) {
  for (int k = 0; k < 6; ++k) v[k] = in[k];
}
void put(const Mat2& m, double* out) {  // row by row
  out[0] = m(0, 0);
  out[1] = m(0, 1);
  out[2] = m(1, 0);
  out[3] = m(1, 1);
}
void take(Mat2& m, const double* in) {
  m(0, 0) = in[0];
  m(0, 1) = in[1];
  m(1, 0) = in[2];
  m(1, 1) = in[3];
}

// The dimensions of one particle's value of type T (after the particle dimension).
template <class T>
std::vector<hsize_t> value_dims() {
  if constexpr (std::is_same_v<T, double>) {
    return {};
  } else if constexpr (std::is_same_v<T, Vec2>) {
    return {2};
  } else if constexpr (std::is_same_v<T, Vec6>) {
    return {6};
  } else {
    static_assert(std::is_same_v<T, Mat2>, "a particle field of a type the checkpoint lacks");
    return {2, 2};
  }
}

struct ParticleField {
  const char* name;
  std::vector<hsize_t> value_dims;
  void (*get)(const Particles&, std::size_t, double*);
  void (*set)(Particles&, std::size_t, const double*);
  std::size_t width() const {
    return std::accumulate(value_dims.begin(), value_dims.end(), hsize_t{1},
                           std::multiplies<hsize_t>());
  }
};

template <auto member>  // std::vector<T> Particles::*
ParticleField particle_field(const char* name) {
  using T = typename std::remove_cvref_t<decltype(std::declval<Particles&>().*member)>::value_type;
  return {name, value_dims<T>(),
          [](const Particles& p, std::size_t i, double* out) { put((p.*member)[i], out); },
          [](Particles& p, std::size_t i, const double* in) { take((p.*member)[i], in); }};
}

template <auto member>  // T MaterialState::*
ParticleField state_field(const char* name) {
  using T = std::remove_cvref_t<decltype(std::declval<MaterialState&>().*member)>;
  return {name, value_dims<T>(),
          [](const Particles& p, std::size_t i, double* out) { put(p.state[i].*member, out); },
          [](Particles& p, std::size_t i, const double* in) { take(p.state[i].*member, in); }};
}

// Every double field of the particles (the material index, an int, is stored beside them).
const std::vector<ParticleField>& particle_fields() {
  static const std::vector<ParticleField> fields = {
      particle_field<&Particles::position>("position"),
      particle_field<&Particles::velocity>("velocity"),
      particle_field<&Particles::mass>("mass"),
      particle_field<&Particles::initial_volume>("initial_volume"),
      particle_field<&Particles::volume>("volume"),
      particle_field<&Particles::initial_half_size>("initial_half_size"),
      particle_field<&Particles::half_size>("half_size"),
      particle_field<&Particles::deformation_gradient>("deformation_gradient"),
      particle_field<&Particles::out_of_plane_stretch>("out_of_plane_stretch"),
      particle_field<&Particles::external_force>("external_force"),
      state_field<&MaterialState::stress>("stress"),
      state_field<&MaterialState::void_ratio>("void_ratio"),
  };
  return fields;
}

// One dataset of /particles/history: a history variable by name, as some model declares it.
struct HistoryDataset {
  std::string name;
  int size;
};

// Every history variable the models declare, once by name (the sizes must agree).
std::vector<HistoryDataset> history_datasets(const std::vector<ModelPtr>& models) {
  std::vector<HistoryDataset> result;
  for (const ModelPtr& model : models)
    for (const HistoryVariable& v : model->history_variables()) {
      const auto same = std::find_if(result.begin(), result.end(),
                                     [&](const HistoryDataset& d) { return d.name == v.name; });
      if (same == result.end())
        result.push_back({v.name, v.size});
      else if (same->size != v.size)
        throw Error(
            fmt::format("checkpoint: two models declare the history variable {} with "
                        "sizes {} and {}",
                        v.name, same->size, v.size));
    }
  return result;
}

// Where the model keeps the named variable (nullptr: it does not declare it).
const HistoryVariable* find_history(const ConstitutiveModel& model, const std::string& name) {
  for (const HistoryVariable& v : model.history_variables())
    if (name == v.name) return &v;
  return nullptr;
}

std::vector<double> flatten(const std::vector<Vec2>& points) {
  std::vector<double> values(2 * points.size());
  for (std::size_t i = 0; i < points.size(); ++i) put(points[i], &values[2 * i]);
  return values;
}

std::vector<Vec2> unflatten(const std::vector<double>& values) {
  std::vector<Vec2> points(values.size() / 2);
  for (std::size_t i = 0; i < points.size(); ++i) take(points[i], &values[2 * i]);
  return points;
}

// ---------------------------------------------------------------------------------------------
// Writing

class Writer {
 public:
  explicit Writer(std::string file) : file_(std::move(file)) {}

  Handle create_file() const {
    // The latest format: its metadata carries checksums (see the layout above).
    const Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    if (!access.valid() ||
        H5Pset_libver_bounds(access.get(), H5F_LIBVER_LATEST, H5F_LIBVER_LATEST) < 0)
      fail_hdf5("the file access properties");
    Handle file(H5Fcreate(file_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()), H5Fclose);
    if (!file.valid()) {
      const int saved = errno;
      fail(fmt::format("cannot create it: {}",
                       saved != 0 ? std::string(std::strerror(saved)) : hdf5_error_text()));
    }
    return file;
  }

  Handle group(hid_t parent, const char* name) const {
    Handle g(H5Gcreate2(parent, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    if (!g.valid()) fail_hdf5(fmt::format("group {}", name));
    return g;
  }

  void attribute(hid_t loc, const char* name, hid_t memory_type, const void* value) const {
    Handle space(H5Screate(H5S_SCALAR), H5Sclose);
    Handle attr;
    if (space.valid())
      attr = Handle(H5Acreate2(loc, name, memory_type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                    H5Aclose);
    if (!attr.valid() || H5Awrite(attr.get(), memory_type, value) < 0)
      fail_hdf5(fmt::format("attribute {}", name));
  }
  void attribute(hid_t loc, const char* name, double value) const {
    attribute(loc, name, H5T_NATIVE_DOUBLE, &value);
  }
  void attribute(hid_t loc, const char* name, std::int64_t value) const {
    attribute(loc, name, H5T_NATIVE_INT64, &value);
  }
  void attribute(hid_t loc, const char* name, const std::string& value) const {
    const Handle type = string_type(value.size());
    if (!type.valid()) fail_hdf5(fmt::format("attribute {}", name));
    std::string padded = value;
    padded.resize(std::max<std::size_t>(value.size(), 1), '\0');
    attribute(loc, name, type.get(), padded.data());
  }

  // A dataset of `dims` from `data` (of the memory type; nothing is read when it is empty).
  void dataset(hid_t loc, const char* name, hid_t memory_type, const std::vector<hsize_t>& dims,
               const void* data) const {
    Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
    Handle set;
    if (space.valid())
      set = Handle(
          H5Dcreate2(loc, name, memory_type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
          H5Dclose);
    const bool empty = std::find(dims.begin(), dims.end(), hsize_t{0}) != dims.end();
    if (!set.valid() ||
        (!empty && H5Dwrite(set.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0))
      fail_hdf5(fmt::format("dataset {}", name));
    checksum(set.get(), empty ? nullptr : data, empty ? 0 : byte_count(memory_type, dims));
  }
  // The checksum attribute of a dataset whose bytes (as written) are `data`.
  void checksum(hid_t set, const void* data, std::size_t size) const {
    const std::uint64_t hash = content_hash(data, size);
    attribute(set, "checksum", H5T_NATIVE_UINT64, &hash);
  }
  void doubles(hid_t loc, const char* name, const std::vector<hsize_t>& dims,
               const std::vector<double>& values) const {
    dataset(loc, name, H5T_NATIVE_DOUBLE, dims, values.data());
  }
  void points(hid_t loc, const char* name, const std::vector<Vec2>& values) const {
    doubles(loc, name, {values.size(), 2}, flatten(values));
  }
  void vector(hid_t loc, const char* name, const Vec2& value) const {
    doubles(loc, name, {2}, {value.x(), value.y()});
  }
  // A string of any bytes as a scalar dataset, with its length as an attribute.
  void text(hid_t loc, const char* name, const std::string& value) const {
    const Handle type = string_type(value.size());
    Handle space(H5Screate(H5S_SCALAR), H5Sclose);
    Handle set;
    if (type.valid() && space.valid())
      set = Handle(
          H5Dcreate2(loc, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
          H5Dclose);
    std::string padded = value;
    padded.resize(std::max<std::size_t>(value.size(), 1), '\0');
    if (!set.valid() ||
        H5Dwrite(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, padded.data()) < 0)
      fail_hdf5(fmt::format("dataset {}", name));
    attribute(set.get(), "length", static_cast<std::int64_t>(value.size()));
    checksum(set.get(), padded.data(), padded.size());
  }

  [[noreturn]] void fail(const std::string& why) const {
    throw Error(fmt::format("cannot write checkpoint {}: {}", file_, why));
  }
  [[noreturn]] void fail_hdf5(const std::string& what) const {
    const std::string detail = hdf5_error_text();
    fail(fmt::format("HDF5 could not write {}{}", what, detail.empty() ? "" : ": " + detail));
  }

 private:
  std::string file_;
};

void write_particles(const Writer& w, hid_t root, const Particles& particles,
                     const std::vector<ModelPtr>& models) {
  const Handle group = w.group(root, "particles");
  const std::size_t n = particles.size();
  std::vector<double> values;
  for (const ParticleField& field : particle_fields()) {
    const std::size_t width = field.width();
    values.assign(n * width, 0.0);
    for (std::size_t p = 0; p < n; ++p) field.get(particles, p, &values[p * width]);
    std::vector<hsize_t> dims{n};
    dims.insert(dims.end(), field.value_dims.begin(), field.value_dims.end());
    w.doubles(group.get(), field.name, dims, values);
  }
  w.dataset(group.get(), "material", H5T_NATIVE_INT, {n}, particles.material.data());
  const Handle history = w.group(group.get(), "history");
  for (const HistoryDataset& d : history_datasets(models)) {
    const std::size_t size = static_cast<std::size_t>(d.size);
    values.assign(n * size, 0.0);
    for (std::size_t p = 0; p < n; ++p) {
      const HistoryVariable* v =
          find_history(*models[static_cast<std::size_t>(particles.material[p])], d.name);
      if (v == nullptr) continue;
      const double* from = particles.state[p].history.data() + v->offset;
      std::copy(from, from + size, &values[p * size]);
    }
    w.doubles(history.get(), d.name.c_str(), {n, size}, values);
  }
}

void write_bodies(const Writer& w, hid_t root, const mpm::MpmState& solver,
                  const mpm::SolverRunState& state) {
  const Handle group = w.group(root, "bodies");
  for (int b = 0; b < solver.rigid_body_count(); ++b) {
    const RigidBody& body = solver.rigid_body(b);
    const Handle g = w.group(group.get(), std::to_string(b).c_str());
    w.attribute(g.get(), "kind", std::string(body.axisymmetric() ? "pile" : "polygon"));
    w.attribute(g.get(), "part_count", static_cast<std::int64_t>(body.part_count()));
    w.attribute(g.get(), "friction", body.friction());
    w.attribute(g.get(), "contact_distance", body.contact_distance());
    w.points(g.get(), "vertices", body.vertices());
    w.vector(g.get(), "displacement", body.displacement());
    w.vector(g.get(), "velocity", body.velocity());
    const mpm::RigidBodyForce& force = state.rigid_body_forces.at(static_cast<std::size_t>(b));
    w.vector(g.get(), "contact_force", force.total);
    w.points(g.get(), "contact_force_parts", force.parts);
  }
}

void write_run_state(const Writer& w, hid_t root, const mpm::SolverRunState& state) {
  const Handle g = w.group(root, "run_state");
  w.attribute(g.get(), "time", state.time);
  w.attribute(g.get(), "steps", static_cast<std::int64_t>(state.steps));
  w.attribute(g.get(), "max_wave_speed", state.max_wave_speed);
  w.attribute(g.get(), "wave_speed_step", static_cast<std::int64_t>(state.wave_speed_step));
  w.attribute(g.get(), "max_particle_speed", state.max_particle_speed);
  const Handle e = w.group(g.get(), "energies");
  const mpm::Energies& energies = state.energies;
  w.attribute(e.get(), "kinetic", energies.kinetic);
  w.attribute(e.get(), "internal", energies.internal);
  w.attribute(e.get(), "external_work", energies.external_work);
  w.attribute(e.get(), "damping", energies.damping);
  w.attribute(e.get(), "contact_work", energies.contact_work);
  w.attribute(e.get(), "absorbed", energies.absorbed);
  if (state.scheme_arrays.empty()) return;
  // The analysis's own arrays, by index, each with its name.
  const Handle arrays = w.group(g.get(), "scheme");
  w.attribute(arrays.get(), "count", static_cast<std::int64_t>(state.scheme_arrays.size()));
  std::int64_t index = 0;
  for (const auto& [name, values] : state.scheme_arrays) {
    const std::string key = std::to_string(index++);
    w.doubles(arrays.get(), key.c_str(), {values.size()}, values);
    const Handle set(H5Dopen2(arrays.get(), key.c_str(), H5P_DEFAULT), H5Dclose);
    if (!set.valid()) w.fail_hdf5(fmt::format("dataset run_state/scheme/{}", key));
    w.attribute(set.get(), "name", name);
  }
}

void write_run_info(const Writer& w, hid_t root, const MpmCheckpointInfo& info) {
  const Handle g = w.group(root, "run");
  w.attribute(g.get(), "case_source", info.case_source);
  w.attribute(g.get(), "next_phase", static_cast<std::int64_t>(info.next_phase));
  w.attribute(g.get(), "phase_start", info.phase_start);
  w.points(g.get(), "initial_position", info.initial_position);
  const Handle records = w.group(g.get(), "records");
  w.attribute(records.get(), "count", static_cast<std::int64_t>(info.records.size()));
  std::int64_t index = 0;
  for (const auto& [name, content] : info.records) {
    const std::string key = std::to_string(index++);
    w.text(records.get(), key.c_str(), content);
    const Handle set(H5Dopen2(records.get(), key.c_str(), H5P_DEFAULT), H5Dclose);
    if (!set.valid()) w.fail_hdf5(fmt::format("dataset run/records/{}", key));
    w.attribute(set.get(), "name", name);
  }
}

void write_checkpoint_file(const Writer& w, const mpm::MpmState& solver,
                           const MpmCheckpointInfo& info) {
  const std::size_t n = solver.particles().size();
  if (!info.initial_position.empty() && info.initial_position.size() != n)
    w.fail(fmt::format("initial_position has {} entries: must be 0 or the particle count {}",
                       info.initial_position.size(), n));
  const mpm::SolverRunState state = solver.run_state();
  Handle file = w.create_file();
  {
    const Handle root(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose);
    if (!root.valid()) w.fail_hdf5("the root group");
    const hid_t r = root.get();
    w.attribute(r, "format", std::string(kFormat));
    w.attribute(r, "format_version", std::int64_t{kMpmCheckpointFormatVersion});
    w.attribute(r, "geometry", std::string(geometry_name(solver.geometry())));
    w.attribute(r, "analysis", std::string(solver.analysis()));
    w.attribute(r, "grid_nx", std::int64_t{solver.grid().nx()});
    w.attribute(r, "grid_ny", std::int64_t{solver.grid().ny()});
    w.attribute(r, "particle_count", static_cast<std::int64_t>(n));
    w.attribute(r, "materials_count", static_cast<std::int64_t>(solver.materials().size()));
    w.attribute(r, "body_count", std::int64_t{solver.rigid_body_count()});
    w.attribute(r, "threads", std::int64_t{solver.threads()});
    const Handle grid = w.group(r, "grid");
    const std::vector<double>& x = solver.grid().x_axis().nodes();
    const std::vector<double>& y = solver.grid().y_axis().nodes();
    w.doubles(grid.get(), "x_nodes", {x.size()}, x);
    w.doubles(grid.get(), "y_nodes", {y.size()}, y);
    write_particles(w, r, solver.particles(), solver.materials());
    write_bodies(w, r, solver, state);
    write_run_state(w, r, state);
    write_run_info(w, r, info);
  }
  if (!file.close()) w.fail_hdf5("the file (on closing it)");
}

// Flushes the file's data to the disk, so that the rename publishes a complete file.
bool sync_file(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  ::close(fd);
  return ok;
}

// ---------------------------------------------------------------------------------------------
// Reading

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& value,
                         const std::string& reason) const {
    throw InputError(file_, 0, key, value, reason);
  }
  [[noreturn]] void fail_hdf5(const std::string& key, const std::string& what) const {
    const std::string detail = hdf5_error_text();
    fail(key, "", fmt::format("{}{}", what, detail.empty() ? "" : " (" + detail + ")"));
  }

  Handle open_file() const {
    std::error_code ec;
    if (!fs::is_regular_file(file_, ec)) fail("", "", "no such checkpoint file");
#if H5_VERSION_GE(1, 12, 0)
    const htri_t is_hdf5 = H5Fis_accessible(file_.c_str(), H5P_DEFAULT);
#else
    const htri_t is_hdf5 = H5Fis_hdf5(file_.c_str());
#endif
    if (is_hdf5 <= 0)
      fail("", "", "not an HDF5 file (a checkpoint written by pilempm is expected)");
    Handle file(H5Fopen(file_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) fail_hdf5("", "cannot open the HDF5 file (damaged?)");
    return file;
  }

  Handle group(hid_t parent, const std::string& path) const {
    if (H5Lexists(parent, path.c_str(), H5P_DEFAULT) <= 0) fail(path, "", "missing");
    Handle g(H5Gopen2(parent, path.c_str(), H5P_DEFAULT), H5Gclose);
    if (!g.valid()) fail_hdf5(path, "cannot open the group");
    return g;
  }

  // Attribute `name` of `loc` (`where` names loc in messages), of HDF5 class `type_class`.
  Handle attribute(hid_t loc, const std::string& where, const char* name,
                   H5T_class_t type_class) const {
    const std::string key = attribute_key(where, name);
    if (H5Aexists(loc, name) <= 0) fail(key, "", "missing");
    Handle attr(H5Aopen(loc, name, H5P_DEFAULT), H5Aclose);
    if (!attr.valid()) fail_hdf5(key, "cannot open the attribute");
    const Handle type(H5Aget_type(attr.get()), H5Tclose);
    const Handle space(H5Aget_space(attr.get()), H5Sclose);
    if (!type.valid() || H5Tget_class(type.get()) != type_class || !space.valid() ||
        H5Sget_simple_extent_npoints(space.get()) != 1)
      fail(key, "", "has the wrong type or shape");
    return attr;
  }
  double real(hid_t loc, const std::string& where, const char* name) const {
    const Handle attr = attribute(loc, where, name, H5T_FLOAT);
    double value = 0.0;
    if (H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &value) < 0)
      fail_hdf5(attribute_key(where, name), "cannot read");
    return value;
  }
  std::int64_t integer(hid_t loc, const std::string& where, const char* name) const {
    const Handle attr = attribute(loc, where, name, H5T_INTEGER);
    std::int64_t value = 0;
    if (H5Aread(attr.get(), H5T_NATIVE_INT64, &value) < 0)
      fail_hdf5(attribute_key(where, name), "cannot read");
    return value;
  }
  std::string string(hid_t loc, const std::string& where, const char* name) const {
    const Handle attr = attribute(loc, where, name, H5T_STRING);
    const Handle type(H5Aget_type(attr.get()), H5Tclose);
    if (H5Tis_variable_str(type.get()) != 0)
      fail(attribute_key(where, name), "", "is a variable-length string (fixed length expected)");
    std::string value(H5Tget_size(type.get()), '\0');
    if (value.empty() || H5Aread(attr.get(), type.get(), value.data()) < 0)
      fail_hdf5(attribute_key(where, name), "cannot read");
    value.erase(value.find_last_not_of('\0') + 1);  // the NUL padding
    return value;
  }

  // Dataset `name` of `loc` (`where` names loc), of class `type_class` and shape `dims`.
  Handle dataset(hid_t loc, const std::string& where, const std::string& name,
                 H5T_class_t type_class, const std::vector<hsize_t>& dims) const {
    const std::string key = where + "/" + name;
    if (H5Lexists(loc, name.c_str(), H5P_DEFAULT) <= 0) fail(key, "", "missing");
    Handle set(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose);
    if (!set.valid()) fail_hdf5(key, "cannot open the dataset");
    const Handle type(H5Dget_type(set.get()), H5Tclose);
    if (!type.valid() || H5Tget_class(type.get()) != type_class)
      fail(key, "", "has the wrong type");
    if (type_class == H5T_FLOAT && H5Tget_size(type.get()) != sizeof(double))
      fail(key, "", "is not stored as doubles");
    const std::vector<hsize_t> found = shape(set.get(), key);
    if (found != dims)
      fail(key, shape_text(found), fmt::format("the shape must be {}", shape_text(dims)));
    return set;
  }
  std::vector<hsize_t> shape(hid_t set, const std::string& key) const {
    const Handle space(H5Dget_space(set), H5Sclose);
    const int rank = space.valid() ? H5Sget_simple_extent_ndims(space.get()) : -1;
    if (rank < 0) fail_hdf5(key, "cannot read the shape");
    std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
    if (rank > 0 && H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr) < 0)
      fail_hdf5(key, "cannot read the shape");
    return dims;
  }
  // The first dimension of a dataset's shape (0 when it is a scalar or missing: reported later).
  hsize_t length(hid_t loc, const std::string& where, const std::string& name) const {
    if (H5Lexists(loc, name.c_str(), H5P_DEFAULT) <= 0) fail(where + "/" + name, "", "missing");
    const Handle set(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose);
    if (!set.valid()) fail_hdf5(where + "/" + name, "cannot open the dataset");
    const std::vector<hsize_t> dims = shape(set.get(), where + "/" + name);
    return dims.empty() ? 0 : dims.front();
  }
  static std::string shape_text(const std::vector<hsize_t>& dims) {
    return fmt::format("({})", fmt::join(dims, ", "));
  }

  void read(hid_t loc, const std::string& where, const std::string& name, H5T_class_t type_class,
            hid_t memory_type, const std::vector<hsize_t>& dims, void* data) const {
    const Handle set = dataset(loc, where, name, type_class, dims);
    const bool empty = std::find(dims.begin(), dims.end(), hsize_t{0}) != dims.end();
    if (!empty && H5Dread(set.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
      fail_hdf5(where + "/" + name, "cannot read (the file may be damaged)");
    verify(set.get(), where + "/" + name, empty ? nullptr : data,
           empty ? 0 : byte_count(memory_type, dims));
  }
  // Compares the bytes read from a dataset with the checksum stored when it was written.
  void verify(hid_t set, const std::string& key, const void* data, std::size_t size) const {
    const Handle attr = attribute(set, key, "checksum", H5T_INTEGER);
    std::uint64_t stored = 0;
    if (H5Aread(attr.get(), H5T_NATIVE_UINT64, &stored) < 0)
      fail_hdf5(attribute_key(key, "checksum"), "cannot read");
    if (stored != content_hash(data, size))
      fail(key, "",
           "damaged: its data do not match the checksum stored when it was written (the file "
           "was changed afterwards; restart from another checkpoint)");
  }
  std::vector<double> doubles(hid_t loc, const std::string& where, const std::string& name,
                              const std::vector<hsize_t>& dims) const {
    std::vector<double> values(
        std::accumulate(dims.begin(), dims.end(), hsize_t{1}, std::multiplies<hsize_t>()));
    read(loc, where, name, H5T_FLOAT, H5T_NATIVE_DOUBLE, dims, values.data());
    return values;
  }
  std::vector<Vec2> points(hid_t loc, const std::string& where, const std::string& name,
                           hsize_t count) const {
    return unflatten(doubles(loc, where, name, {count, 2}));
  }
  Vec2 vector(hid_t loc, const std::string& where, const std::string& name) const {
    const std::vector<double> v = doubles(loc, where, name, {2});
    return Vec2(v[0], v[1]);
  }
  std::string text(hid_t loc, const std::string& where, const std::string& name) const {
    const std::string key = where + "/" + name;
    const Handle set = dataset(loc, where, name, H5T_STRING, {});
    const Handle type(H5Dget_type(set.get()), H5Tclose);
    if (H5Tis_variable_str(type.get()) != 0)
      fail(key, "", "is a variable-length string (fixed length expected)");
    std::string value(H5Tget_size(type.get()), '\0');
    if (value.empty() ||
        H5Dread(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, value.data()) < 0)
      fail_hdf5(key, "cannot read (the file may be damaged)");
    verify(set.get(), key, value.data(), value.size());
    const std::int64_t length = integer(set.get(), key, "length");
    if (length < 0 || static_cast<std::size_t>(length) > value.size())
      fail(key + "@length", std::to_string(length),
           fmt::format("must be in [0, {}] (the stored size)", value.size()));
    value.resize(static_cast<std::size_t>(length));
    return value;
  }

  const std::string& file() const {
    return file_;
  }
  // How messages name attribute `name` of the object at `where` ("" for the root: the name).
  static std::string attribute_key(const std::string& where, const char* name) {
    return where.empty() ? std::string(name) : where + "@" + name;
  }

 private:
  std::string file_;
};

// The header's counts against the solver's: the checkpoint must come from the same case.
void check_header(const Reader& r, hid_t root, const mpm::MpmState& solver) {
  const std::string format = r.string(root, "", "format");
  if (format != kFormat)
    r.fail("format", format, fmt::format("must be \"{}\" (not a pilempm checkpoint)", kFormat));
  const std::int64_t version = r.integer(root, "", "format_version");
  if (version != kMpmCheckpointFormatVersion)
    r.fail("format_version", std::to_string(version),
           fmt::format("this pilempm reads version {}", kMpmCheckpointFormatVersion));
  const std::string geometry = r.string(root, "", "geometry");
  const char* expected_geometry = geometry_name(solver.geometry());
  if (geometry != expected_geometry)
    r.fail("geometry", geometry,
           fmt::format("the case is {} (a checkpoint continues the case it came from)",
                       expected_geometry));
  const std::string analysis = r.string(root, "", "analysis");
  if (analysis != solver.analysis())
    r.fail("analysis", analysis,
           fmt::format("the case runs the {} analysis (a checkpoint continues the analysis it "
                       "came from)",
                       solver.analysis()));
  const auto check_count = [&](const char* name, std::int64_t expected, const char* what) {
    const std::int64_t value = r.integer(root, "", name);
    if (value != expected)
      r.fail(name, std::to_string(value),
             fmt::format("the case has {} {} (a checkpoint continues the case it came from)",
                         expected, what));
  };
  check_count("grid_nx", solver.grid().nx(), "grid nodes along x");
  check_count("grid_ny", solver.grid().ny(), "grid nodes along y");
  check_count("particle_count", static_cast<std::int64_t>(solver.particles().size()), "particles");
  check_count("materials_count", static_cast<std::int64_t>(solver.materials().size()), "materials");
  check_count("body_count", solver.rigid_body_count(), "rigid bodies");
}

// The particles of the file, checked against the solver's grid and materials.
Particles read_particles(const Reader& r, hid_t root, const mpm::MpmState& solver) {
  const Handle group = r.group(root, "particles");
  const hid_t g = group.get();
  const std::string where = "/particles";
  Particles particles = solver.particles();  // every field has the right length; all replaced
  const std::size_t n = particles.size();
  for (const ParticleField& field : particle_fields()) {
    std::vector<hsize_t> dims{n};
    dims.insert(dims.end(), field.value_dims.begin(), field.value_dims.end());
    const std::vector<double> values = r.doubles(g, where, field.name, dims);
    const std::size_t width = field.width();
    for (std::size_t p = 0; p < n; ++p) field.set(particles, p, &values[p * width]);
  }
  r.read(g, where, "material", H5T_INTEGER, H5T_NATIVE_INT, {n}, particles.material.data());

  const int materials = static_cast<int>(solver.materials().size());
  const mpm::Grid& grid = solver.grid();
  const bool axisymmetric = solver.geometry() == mpm::Geometry::axisymmetric;
  for (std::size_t p = 0; p < n; ++p) {
    const auto key = [&](const char* field) { return fmt::format("{}/{}[{}]", where, field, p); };
    if (particles.material[p] < 0 || particles.material[p] >= materials)
      r.fail(key("material"), std::to_string(particles.material[p]),
             fmt::format("must be in [0, {}] (the case's materials)", materials - 1));
    const Vec2& x = particles.position[p];
    if (!(x.allFinite() && grid.contains(x.x(), x.y()) && (!axisymmetric || x.x() > 0.0)))
      r.fail(key("position"), fmt::format("({}, {})", format_value(x.x()), format_value(x.y())),
             axisymmetric ? "must lie inside the case's grid at r > 0"
                          : "must lie inside the case's grid");
    if (!(particles.mass[p] > 0.0 && std::isfinite(particles.mass[p])))
      r.fail(key("mass"), format_value(particles.mass[p]), "must be > 0");
    if (!(particles.volume[p] > 0.0 && std::isfinite(particles.volume[p])))
      r.fail(key("volume"), format_value(particles.volume[p]), "must be > 0");
  }

  // The history variables the case's models declare; other slots are zero.
  for (std::size_t p = 0; p < n; ++p) particles.state[p].history.fill(0.0);
  const Handle history = r.group(g, "history");
  const std::string history_where = where + "/history";
  const std::vector<ModelPtr>& models = solver.materials();
  for (const HistoryDataset& d : history_datasets(models)) {
    const std::size_t size = static_cast<std::size_t>(d.size);
    const std::vector<double> values =
        r.doubles(history.get(), history_where, d.name.c_str(), {n, size});
    for (std::size_t p = 0; p < n; ++p) {
      const HistoryVariable* v =
          find_history(*models[static_cast<std::size_t>(particles.material[p])], d.name);
      if (v == nullptr) continue;
      std::copy(&values[p * size], &values[p * size] + size,
                particles.state[p].history.data() + v->offset);
    }
  }
  return particles;
}

// The rigid bodies of the file (copies of the solver's, moved to where the file has them) and
// their contact forces.
void read_bodies(const Reader& r, hid_t root, const mpm::MpmState& solver,
                 std::vector<RigidBody>& bodies, std::vector<mpm::RigidBodyForce>& forces) {
  const Handle group = r.group(root, "bodies");
  for (int b = 0; b < solver.rigid_body_count(); ++b) {
    const std::string name = std::to_string(b);
    const std::string where = "/bodies/" + name;
    const Handle handle = r.group(group.get(), name);
    const hid_t g = handle.get();
    RigidBody body = solver.rigid_body(b);
    const std::string kind = r.string(g, where, "kind");
    const char* expected_kind = body.axisymmetric() ? "pile" : "polygon";
    if (kind != expected_kind)
      r.fail(where + "@kind", kind,
             fmt::format("rigid body {} of the case is a {}", b, expected_kind));
    const std::size_t vertices = body.vertices().size();
    const hsize_t stored_vertices = r.length(g, where, "vertices");
    if (stored_vertices != vertices)
      r.fail(where + "/vertices", fmt::format("{} vertices", stored_vertices),
             fmt::format("rigid body {} of the case has {}", b, vertices));
    const std::int64_t parts = r.integer(g, where, "part_count");
    if (parts != body.part_count())
      r.fail(where + "@part_count", std::to_string(parts),
             fmt::format("rigid body {} of the case has {} surface parts", b, body.part_count()));
    const std::vector<Vec2> position = r.points(g, where, "vertices", vertices);
    const Vec2 displacement = r.vector(g, where, "displacement");
    const Vec2 velocity = r.vector(g, where, "velocity");
    const double friction = r.real(g, where, "friction");
    const double contact_distance = r.real(g, where, "contact_distance");
    mpm::RigidBodyForce force;
    force.total = r.vector(g, where, "contact_force");
    force.parts = r.points(g, where, "contact_force_parts", static_cast<hsize_t>(parts));
    try {
      body.restore_position(position, displacement);
      body.set_velocity(velocity);
      body.set_friction(friction);
      body.set_contact_distance(contact_distance);
    } catch (const InvalidValue& e) {
      r.fail(where, "", e.what());
    }
    bodies.push_back(std::move(body));
    forces.push_back(std::move(force));
  }
}

mpm::SolverRunState read_run_state(const Reader& r, hid_t root) {
  const Handle group = r.group(root, "run_state");
  const hid_t g = group.get();
  const std::string where = "/run_state";
  mpm::SolverRunState state;
  state.time = r.real(g, where, "time");
  state.steps = static_cast<long>(r.integer(g, where, "steps"));
  state.max_wave_speed = r.real(g, where, "max_wave_speed");
  state.wave_speed_step = static_cast<long>(r.integer(g, where, "wave_speed_step"));
  state.max_particle_speed = r.real(g, where, "max_particle_speed");
  const Handle energies = r.group(g, "energies");
  const std::string at = where + "/energies";
  const hid_t e = energies.get();
  state.energies.kinetic = r.real(e, at, "kinetic");
  state.energies.internal = r.real(e, at, "internal");
  state.energies.external_work = r.real(e, at, "external_work");
  state.energies.damping = r.real(e, at, "damping");
  state.energies.contact_work = r.real(e, at, "contact_work");
  state.energies.absorbed = r.real(e, at, "absorbed");
  if (H5Lexists(g, "scheme", H5P_DEFAULT) <= 0) return state;
  const Handle arrays = r.group(g, "scheme");
  const std::string in = where + "/scheme";
  const std::int64_t count = r.integer(arrays.get(), in, "count");
  if (count < 0 || count > 1000)
    r.fail(in + "@count", std::to_string(count), "must be in [0, 1000]");
  for (std::int64_t k = 0; k < count; ++k) {
    const std::string key = std::to_string(k);
    std::vector<double> values =
        r.doubles(arrays.get(), in, key, {r.length(arrays.get(), in, key)});
    const Handle set(H5Dopen2(arrays.get(), key.c_str(), H5P_DEFAULT), H5Dclose);
    if (!set.valid()) r.fail_hdf5(in + "/" + key, "cannot open the dataset");
    state.scheme_arrays.emplace_back(r.string(set.get(), in + "/" + key, "name"),
                                     std::move(values));
  }
  return state;
}

MpmCheckpointInfo read_run_info(const Reader& r, hid_t root, std::size_t particle_count) {
  const Handle group = r.group(root, "run");
  const hid_t g = group.get();
  const std::string where = "/run";
  MpmCheckpointInfo info;
  info.case_source = r.string(g, where, "case_source");
  const std::int64_t next_phase = r.integer(g, where, "next_phase");
  if (next_phase < 0 || next_phase > std::numeric_limits<int>::max())
    r.fail(where + "@next_phase", std::to_string(next_phase), "must be >= 0");
  info.next_phase = static_cast<int>(next_phase);
  info.phase_start = r.real(g, where, "phase_start");
  const hsize_t initial = r.length(g, where, "initial_position");
  if (initial != 0 && initial != particle_count)
    r.fail(where + "/initial_position", fmt::format("{} points", initial),
           fmt::format("must be 0 or the particle count {}", particle_count));
  info.initial_position = r.points(g, where, "initial_position", initial);
  const Handle records = r.group(g, "records");
  const std::string at = where + "/records";
  const std::int64_t count = r.integer(records.get(), at, "count");
  if (count < 0) r.fail(at + "@count", std::to_string(count), "must be >= 0");
  for (std::int64_t k = 0; k < count; ++k) {
    const std::string key = std::to_string(k);
    std::string content = r.text(records.get(), at, key);
    const Handle set(H5Dopen2(records.get(), key.c_str(), H5P_DEFAULT), H5Dclose);
    if (!set.valid()) r.fail_hdf5(at + "/" + key, "cannot open the dataset");
    const std::string name = r.string(set.get(), at + "/" + key, "name");
    if (!info.records.emplace(name, std::move(content)).second)
      r.fail(at + "/" + key + "@name", name, "is a second record of that name");
  }
  return info;
}

}  // namespace

void write_mpm_checkpoint(const fs::path& file, const mpm::MpmState& solver,
                          const MpmCheckpointInfo& info) {
  const fs::path tmp = temporary_path_for(file);
  const QuietHdf5Errors quiet;
  try {
    const Writer writer(tmp.string());
    write_checkpoint_file(writer, solver, info);
    if (!sync_file(tmp)) writer.fail(fmt::format("cannot sync it: {}", std::strerror(errno)));
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw Error(fmt::format("cannot write checkpoint {}: cannot rename {} to it: {}", file.string(),
                            tmp.string(), ec.message()));
  }
}

MpmCheckpointInfo read_mpm_checkpoint(const fs::path& file, mpm::MpmState& solver) {
  const QuietHdf5Errors quiet;
  const Reader reader(file.string());
  MpmCheckpointInfo info;
  Particles particles;
  std::vector<RigidBody> bodies;
  mpm::SolverRunState state;
  {
    const Handle handle = reader.open_file();
    const Handle root(H5Gopen2(handle.get(), "/", H5P_DEFAULT), H5Gclose);
    if (!root.valid()) reader.fail_hdf5("/", "cannot open the root group");
    const hid_t r = root.get();
    check_header(reader, r, solver);
    const std::int64_t threads = reader.integer(r, "", "threads");
    particles = read_particles(reader, r, solver);
    read_bodies(reader, r, solver, bodies, state.rigid_body_forces);
    mpm::SolverRunState run = read_run_state(reader, r);
    run.rigid_body_forces = std::move(state.rigid_body_forces);
    state = std::move(run);
    info = read_run_info(reader, r, particles.size());
    info.threads = static_cast<int>(threads);
  }
  // Everything is read and checked: now the solver changes. The run state first, since it
  // checks the forces against the bodies (and changes nothing when they do not fit).
  try {
    solver.restore_run_state(state);
  } catch (const InvalidValue& e) {
    throw InputError(file.string(), 0, "/bodies", "", e.what());
  }
  for (int b = 0; b < solver.rigid_body_count(); ++b)
    solver.rigid_body(b) = std::move(bodies[static_cast<std::size_t>(b)]);
  solver.particles() = std::move(particles);
  return info;
}

}  // namespace pilempm
