// Reading and checking the MPM checkpoint (io/mpm_checkpoint.hpp; the layout in
// checkpoint_layout.hpp).
#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numeric>
#include <utility>

#include "pilempm/core/error.hpp"
#include "pilempm/io/checkpoint/checkpoint_layout.hpp"
#include "pilempm/io/checkpoint/hdf5_handles.hpp"
#include "pilempm/io/element_output.hpp"
#include "pilempm/io/mpm_checkpoint.hpp"

namespace pilempm {

namespace fs = std::filesystem;
using mpm::Particles;
using mpm::RigidBody;
using mpm::Vec2;
using namespace checkpoint;

namespace {

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
// The file is a pilempm checkpoint of the version this build reads.
void check_format(const Reader& r, hid_t root) {
  const std::string format = r.string(root, "", "format");
  if (format != kFormat)
    r.fail("format", format, fmt::format("must be \"{}\" (not a pilempm checkpoint)", kFormat));
  const std::int64_t version = r.integer(root, "", "format_version");
  if (version != kMpmCheckpointFormatVersion)
    r.fail("format_version", std::to_string(version),
           fmt::format("this pilempm reads version {}", kMpmCheckpointFormatVersion));
}

void check_header(const Reader& r, hid_t root, const mpm::MpmState& solver) {
  check_format(r, root);
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

MpmCheckpointInfo read_mpm_checkpoint_info(const fs::path& file) {
  const QuietHdf5Errors quiet;
  const Reader reader(file.string());
  const Handle handle = reader.open_file();
  const Handle root(H5Gopen2(handle.get(), "/", H5P_DEFAULT), H5Gclose);
  if (!root.valid()) reader.fail_hdf5("/", "cannot open the root group");
  check_format(reader, root.get());
  // The initial positions' count is checked against the particles by read_mpm_checkpoint.
  const Handle run = reader.group(root.get(), "run");
  const hsize_t initial = reader.length(run.get(), "/run", "initial_position");
  return read_run_info(reader, root.get(), initial);
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
