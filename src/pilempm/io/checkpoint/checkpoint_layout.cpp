#include "pilempm/io/checkpoint/checkpoint_layout.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <type_traits>
#include <utility>

#include "pilempm/core/error.hpp"

namespace pilempm::checkpoint {

using mpm::Mat2;
using mpm::Particles;
using mpm::Vec2;

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

// The geometry's name as case files spell it.
const char* geometry_name(mpm::Geometry geometry) {
  return geometry == mpm::Geometry::axisymmetric ? "axisymmetric" : "plane-strain";
}

namespace {

// One particle's value as doubles (put) and back (take).
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

}  // namespace

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

}  // namespace pilempm::checkpoint
