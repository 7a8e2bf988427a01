// Binds a C++ configuration struct field by field, so Python holds the very
// struct a controller is created from: each field a property with the
// struct's own default and a setter that names the field when a value has the
// wrong shape or type, `Config(**fields)` that names an unknown keyword,
// `validate()` that runs the one C++ validator, pickling and a repr.
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "numpy_args.hpp"

namespace neurov::bindings {

namespace py = pybind11;

template <typename Config>
class ConfigClass {
 public:
  ConfigClass(py::module_& m, const char* name, const char* doc)
      : cls_(m, name, doc), name_(name), fields_(std::make_shared<Fields>()) {}

  /// A field of any type: `get` returns it as a Python object, `set` stores
  /// a Python value (raising an error that names the field).
  ConfigClass& field(const char* name, std::function<py::object(const Config&)> get,
                     std::function<void(Config&, py::handle)> set, const char* doc) {
    fields_->push_back({name, get, set});
    cls_.def_property(
        name, [get](const Config& c) { return get(c); },
        [set](Config& c, py::handle v) { set(c, v); }, doc);
    return *this;
  }

  /// A fixed-size vector field, e.g. a diagonal gain (6,).
  template <int N>
  ConfigClass& vector(const char* name, Eigen::Matrix<double, N, 1> Config::*member,
                      const char* doc) {
    return field(
        name, [member](const Config& c) { return py::cast(Eigen::Matrix<double, N, 1>(c.*member)); },
        [member, name](Config& c, py::handle v) { c.*member = py_args::vector<N>(v, name); }, doc);
  }

  /// A real-number field.
  ConfigClass& scalar(const char* name, double Config::*member, const char* doc) {
    return field(
        name, [member](const Config& c) { return py::cast(c.*member); },
        [member, name](Config& c, py::handle v) { c.*member = py_args::scalar(v, name); }, doc);
  }

  /// Config(**fields), validate(), pickling and repr; call after the fields.
  py::class_<Config>& finish(const char* what) {
    const auto fields = fields_;
    const std::string cls_name = name_;
    cls_.def(py::init([fields, cls_name](const py::kwargs& kw) {
               Config c;
               for (const auto& item : kw) {
                 const auto key = py::str(item.first).cast<std::string>();
                 const Field* f = find(*fields, key);
                 if (!f)
                   throw py::type_error(cls_name + "() got an unexpected keyword argument '" +
                                        key + "'; its fields are " + names(*fields));
                 f->set(c, item.second);
               }
               return c;
             }),
             "Every field at its default, or as given by keyword (the names of the fields); an "
             "unknown keyword raises TypeError, a bad value names its field.");
    cls_.def(
        "validate",
        [what](const Config& c) { py_args::raise_if_invalid(validate(c), what); },
        "Runs the C++ validator the controller runs when it is built: ValueError naming the "
        "first bad field and what it must be, None when the configuration is valid.");
    cls_.def(py::pickle(
        [fields](const Config& c) {
          py::dict d;
          for (const Field& f : *fields) d[py::str(f.name)] = f.get(c);
          return d;
        },
        [fields](const py::dict& d) {
          Config c;
          // None stands for a field left at its default (a vehicle not yet set).
          for (const Field& f : *fields)
            if (d.contains(f.name) && !d[py::str(f.name)].is_none()) f.set(c, d[py::str(f.name)]);
          return c;
        }));
    cls_.def("__repr__", [fields, cls_name](const Config& c) {
      std::string s = cls_name + "(";
      for (std::size_t i = 0; i < fields->size(); ++i) {
        const Field& f = (*fields)[i];
        s += (i ? ", " : "") + f.name + "=" + std::string(py::repr(f.get(c)));
      }
      return s + ")";
    });
    return cls_;
  }

  py::class_<Config>& cls() { return cls_; }

 private:
  struct Field {
    std::string name;
    std::function<py::object(const Config&)> get;
    std::function<void(Config&, py::handle)> set;
  };
  using Fields = std::vector<Field>;

  static const Field* find(const Fields& fields, const std::string& key) {
    for (const Field& f : fields)
      if (f.name == key) return &f;
    return nullptr;
  }

  static std::string names(const Fields& fields) {
    std::string s;
    for (const Field& f : fields) s += (s.empty() ? "" : ", ") + f.name;
    return s;
  }

  py::class_<Config> cls_;
  std::string name_;
  std::shared_ptr<Fields> fields_;
};

}  // namespace neurov::bindings
