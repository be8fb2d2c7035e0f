#pragma once
// The registry of constitutive models: what a program needs to offer a model in case files,
// build it, describe its parameters and store its state, by the model's name. Adding a model
// is one folder (its class, its parameter reader, its registration) and one line in
// model_registry.cpp (or a register_model() call in a program or test of its own).
//
// The registry knows no file format: a model's reader works on a ParameterSource (io/ implements
// it on its TOML reader) and its description goes to a ParameterSink (io/ writes JSON with it).
// The model's history variables and output fields are declared by the built model itself
// (ConstitutiveModel::history_variables, output_fields), since they may depend on its parameters.
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/constitutive/constitutive_model.hpp"
#include "pilempm/constitutive/integration/embedded_runge_kutta.hpp"
#include "pilempm/constitutive/parameter_source.hpp"

namespace pilempm {

/// A model's parameters as read from input, of the model's own type (see ParametersOf).
class ModelParameters {
 public:
  virtual ~ModelParameters() = default;
};

/// The parameters of type P as ModelParameters.
template <class P>
class ParametersOf final : public ModelParameters {
 public:
  explicit ParametersOf(P parameters) : value(std::move(parameters)) {}
  P value;
};

/// The P inside `parameters` (nullptr when it holds another type).
template <class P>
const P* parameters_as(const ModelParameters* parameters) {
  const auto* typed = dynamic_cast<const ParametersOf<P>*>(parameters);
  return typed ? &typed->value : nullptr;
}

/// Where a model describes its parameters for output (io/ writes them as JSON); keys carry their
/// units as in the input.
class ParameterSink {
 public:
  virtual ~ParameterSink() = default;
  virtual void number(std::string_view key, double value) = 0;  ///< NaN or inf: no value
  virtual void integer(std::string_view key, long value) = 0;
  virtual void text(std::string_view key, std::string_view value) = 0;
  virtual void boolean(std::string_view key, bool value) = 0;
  virtual void begin_group(std::string_view key) = 0;  ///< a nested group of keys
  virtual void end_group() = 0;
  /// A number whose key carries a unit of its own: the reader takes value_in_unit * scale as the
  /// SI value (h_s_MPa: scale 1e6). A writer of case files writes the decimal that reads back to
  /// `value` exactly; by default number(key, value / scale).
  virtual void scaled_number(std::string_view key, double value, double scale) {
    number(key, value / scale);
  }
};

/// One model as the registry knows it.
struct ModelRegistration {
  std::string name;               ///< the value of `model` in a [[material]], e.g. "mohr-coulomb"
  std::vector<std::string> keys;  ///< the keys its table may hold besides name, model and note
  /// Reads the model's keys (strictly: range checks, errors at the key) into its parameters.
  std::function<std::shared_ptr<const ModelParameters>(ParameterSource&)> read;
  /// Builds the model; the integrator settings are for models that integrate rate equations.
  std::function<ModelPtr(const ModelParameters&, const IntegratorSettings&)> make;
  /// Writes the parameters (and the integrator settings where the model uses them).
  std::function<void(const ModelParameters&, const IntegratorSettings&, ParameterSink&)> describe;
  /// The coefficient of earth pressure at rest for a geostatic initial stress by default.
  std::function<double(const ModelParameters&)> at_rest_K0;
  /// Writes the parameters as `read` reads them (the keys of `keys`), so that a [[material]] table
  /// written with them reads back to the same parameters (io/mpm_case_writer.hpp). Empty: the
  /// model's materials cannot be written to a case file.
  std::function<void(const ModelParameters&, ParameterSink&)> write;
};

/// Builds a registration from functions of the model's own parameter type P.
template <class P>
ModelRegistration make_model_registration(
    std::string name, std::vector<std::string> keys, std::function<P(ParameterSource&)> read,
    std::function<ModelPtr(const P&, const IntegratorSettings&)> make,
    std::function<void(const P&, const IntegratorSettings&, ParameterSink&)> describe,
    std::function<double(const P&)> at_rest_K0) {
  auto typed = [](const ModelParameters& p) -> const P& {
    if (const P* value = parameters_as<P>(&p)) return *value;
    throw Error("model registry: parameters of another model");
  };
  ModelRegistration r;
  r.name = std::move(name);
  r.keys = std::move(keys);
  r.read = [read](ParameterSource& source) -> std::shared_ptr<const ModelParameters> {
    return std::make_shared<const ParametersOf<P>>(read(source));
  };
  r.make = [make, typed](const ModelParameters& p, const IntegratorSettings& s) {
    return make(typed(p), s);
  };
  r.describe = [describe, typed](const ModelParameters& p, const IntegratorSettings& s,
                                 ParameterSink& sink) { describe(typed(p), s, sink); };
  r.at_rest_K0 = [at_rest_K0, typed](const ModelParameters& p) { return at_rest_K0(typed(p)); };
  return r;
}

/// Sets the registration's `write` from a function of the model's own parameter type P.
template <class P>
ModelRegistration with_parameter_writer(ModelRegistration registration,
                                        std::function<void(const P&, ParameterSink&)> write) {
  registration.write = [write](const ModelParameters& p, ParameterSink& sink) {
    const P* value = parameters_as<P>(&p);
    if (value == nullptr) throw Error("model registry: parameters of another model");
    write(*value, sink);
  };
  return registration;
}

class ModelRegistry {
 public:
  /// Adds a model; a name already registered is an Error.
  void add(ModelRegistration registration);
  /// The model of this name, or nullptr.
  const ModelRegistration* find(std::string_view name) const;
  /// The model of this name; an Error listing the names when unknown.
  const ModelRegistration& at(std::string_view name) const;
  /// Every registered name, in the order of registration.
  std::vector<std::string> names() const;

 private:
  std::vector<ModelRegistration> models_;
};

/// The program's registry: the library's models, and any a program or test added with
/// register_model (before reading input; registration is not thread-safe).
ModelRegistry& model_registry();
/// Adds a model to model_registry(); returns true (for `static const bool x = register_model()`).
bool register_model(ModelRegistration registration);

}  // namespace pilempm
