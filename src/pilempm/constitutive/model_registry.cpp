#include "pilempm/constitutive/model_registry.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

namespace pilempm {

// Each model's folder defines its registration.
ModelRegistration hypoplastic_registration();
ModelRegistration mohr_coulomb_registration();
ModelRegistration linear_elastic_registration();

void ModelRegistry::add(ModelRegistration registration) {
  if (find(registration.name) != nullptr)
    throw Error(
        fmt::format("model registry: a model \"{}\" is already registered", registration.name));
  models_.push_back(std::move(registration));
}

const ModelRegistration* ModelRegistry::find(std::string_view name) const {
  const auto it = std::find_if(models_.begin(), models_.end(),
                               [&](const ModelRegistration& m) { return m.name == name; });
  return it == models_.end() ? nullptr : &*it;
}

const ModelRegistration& ModelRegistry::at(std::string_view name) const {
  if (const ModelRegistration* r = find(name)) return *r;
  throw Error(
      fmt::format("unknown constitutive model \"{}\": one of {}", name, fmt::join(names(), ", ")));
}

std::vector<std::string> ModelRegistry::names() const {
  std::vector<std::string> result;
  for (const auto& m : models_) result.push_back(m.name);
  return result;
}

ModelRegistry& model_registry() {
  static ModelRegistry registry = [] {
    ModelRegistry r;
    r.add(hypoplastic_registration());
    r.add(mohr_coulomb_registration());
    r.add(linear_elastic_registration());
    return r;
  }();
  return registry;
}

bool register_model(ModelRegistration registration) {
  model_registry().add(std::move(registration));
  return true;
}

}  // namespace pilempm
