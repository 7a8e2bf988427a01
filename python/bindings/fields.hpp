// Binds a plain C++ configuration struct to Python field by field, so that
// Python holds the very C++ object and the C++ validator is the one that
// judges it (the simulation's configs and every controller's). Every setter
// checks the value's type and shape and names `Type.field` when it is wrong:
//  * numbers, bools and enums: by value;
//  * fixed-size vectors: writable numpy views into the struct (the storage is
//    inside it, so a view lives as long as the struct), optionally also set
//    from one number for every entry; square matrices likewise, optionally
//    also set from their diagonal (kDiagonal);
//  * dynamic arrays: read-only copies, assigned whole (a view could outlive a
//    buffer that a later assignment frees);
//  * lists of structs: tuples of copies, assigned whole from any sequence;
//  * nested structs: references into the parent.
//  * anything else: a getter and a setter of its own (`field`).
// Every struct also gets a keyword constructor that refuses unknown names
// (listing the fields), a repr, copy and pickle support, and validate() runs
// the C++ validator. A struct is bound whole from its description
// (config_fields, neurov/core/field_spec.hpp) by Fields<T>::described.
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/typing.h>

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <utility>
#include <vector>

#include "neurov/core/field_spec.hpp"
#include "numpy_args.hpp"
#include "typed_args.hpp"

namespace neurov::bindings {

namespace py = pybind11;

/// How a described field of type D that is not a number, vector, list,
/// optional or bound struct reaches Python: a specialisation with
/// `static void bind(Fields<T>&, const char* name, D T::*member, const char* doc)`
/// (controller_configs.cpp: the NN's modification, the nominal vehicle).
template <typename D>
struct FieldForm {
  static constexpr bool custom = false;
};

/// 1: an Eigen matrix or vector, 2: an optional, 3: a list, 0: anything else.
template <typename X>
struct FieldKind {
  static constexpr int kind = std::is_base_of_v<Eigen::MatrixBase<X>, X> ? 1 : 0;
};
template <typename X>
struct FieldKind<std::optional<X>> {
  static constexpr int kind = 2;
};
template <typename X>
struct FieldKind<std::vector<X>> {
  static constexpr int kind = 3;
  using Element = X;
};

template <typename T>
class Fields {
 public:
  /// T bound from its description (config_fields): each field by its kind,
  /// its docstring from its meaning, unit and rule; the class's FIELDS lists
  /// them as dicts (name, unit, rule, min, max, doc, shape, diagonal,
  /// required) for the readers and the docs' tables. Call validator() and finish() after.
  static Fields described(py::module_& m, const char* name, const char* doc) {
    Fields f(m, name, doc);
    py::list table;
    std::apply([&f, &table](const auto&... s) { (f.add(s, table), ...); },
               config_fields(static_cast<const T*>(nullptr)));
    f.cls_.attr("FIELDS") = py::tuple(table);
    return f;
  }

  /// A field with a conversion of its own: `get(self)` returns it (a
  /// reference is a view into the struct), `set(self, value, "Type.field")`
  /// stores it and names that field in its errors; the type of set's
  /// `value` (typed_args.hpp) is the one the signature declares.
  template <typename Get, typename Set>
  Fields& field(const char* name, Get get, Set set, const char* doc) {
    using Arg = typename SetterArg<decltype(&Set::operator())>::type;
    const std::string qualified = type_ + "." + name;
    cls_.def_property(
        name, get, [set, qualified](T& self, const Arg& v) { set(self, v, qualified); }, doc);
    names_->push_back(name);
    return *this;
  }

  /// validate(): ValueError "`what`: <the C++ validator's message>", None
  /// when valid. `check(config)` returns a ValidationError; by default the
  /// struct's own validate(config).
  template <typename Check>
  Fields& validator(const char* what, Check check) {
    const std::string prefix = what;
    cls_.def(
        "validate",
        [prefix, check](const T& self) { py_args::raise_if_invalid(check(self), prefix.c_str()); },
        "Runs the C++ validator: neurov.ValidationError (a ValueError carrying field, index, "
        "value and expected) naming the first bad field and what it must be, "
        "None when the configuration is valid.");
    return *this;
  }
  Fields& validator(const char* what) {
    return validator(what, [](const T& self) { return validate(self); });
  }

  /// The keyword constructor, repr, copy and pickle; call after the fields.
  /// Returns the class, for methods of its own.
  py::class_<T> finish() {
    auto names = names_;
    const std::string type = type_;
    cls_.def(py::init([names, type](const py::kwargs& kw) {
               auto obj = std::make_unique<T>();
               if (kw.size() > 0) assign(*obj, kw, *names, type);
               return obj;
             }),
             ("Every field is a keyword argument: " + joined(*names) + ".").c_str());
    cls_.def("__repr__", [names, type](const py::object& self) {
      std::string s = type + "(";
      for (std::size_t i = 0; i < names->size(); ++i)
        s += (i ? ", " : "") + (*names)[i] + "=" +
             std::string(py::repr(self.attr((*names)[i].c_str())));
      return s + ")";
    });
    cls_.def("__copy__", [](const T& self) { return T(self); });
    cls_.def("__deepcopy__", [](const T& self, const py::dict&) { return T(self); },
             py::arg("memo"));
    cls_.def(py::pickle(
        [names](const py::object& self) {
          py::dict state;
          for (const auto& n : *names) state[py::str(n)] = self.attr(n.c_str());
          return state;
        },
        [names, type](const py::dict& state) {
          T obj;
          // None stands for a field left at its default (a vehicle not yet set).
          py::dict given;
          for (const auto& item : state)
            if (!item.second.is_none()) given[item.first] = item.second;
          assign(obj, given, *names, type);
          return obj;
        }));
    return cls_;
  }

 private:
  Fields(py::module_& m, const char* name, const char* doc)
      : cls_(m, name, doc), type_(name), names_(std::make_shared<std::vector<std::string>>()) {}

  /// One described field bound by its kind, and its row of FIELDS.
  template <typename D>
  void add(const FieldSpec<T, D>& s, py::list& table) {
    std::string doc = s.doc;
    const std::string rule = check_text(s.check);
    py::object shape = py::none();
    if (*s.unit || !rule.empty()) {
      if (!doc.empty() && doc.back() == '.') doc.pop_back();
      if (*s.unit) doc += std::string(" [") + s.unit + "]";
      if (!rule.empty()) doc += ", " + rule;
    }
    if (doc.empty() || doc.back() != '.') doc += ".";
    if constexpr (FieldForm<D>::custom) {
      FieldForm<D>::bind(*this, s.name, s.member, doc.c_str());
    } else if constexpr (FieldKind<D>::kind == 2) {
      optional(s.name, s.member, doc.c_str());
      using V = typename D::value_type;
      if constexpr (std::is_base_of_v<Eigen::MatrixBase<V>, V>)
        shape = py::make_tuple(static_cast<int>(V::RowsAtCompileTime));
    } else if constexpr (FieldKind<D>::kind == 3) {
      list(s.name, s.member, doc.c_str());
    } else if constexpr (FieldKind<D>::kind == 1) {
      if constexpr (D::RowsAtCompileTime > 0 && D::ColsAtCompileTime == 1) {
        vector(s.name, s.member, s.flags & kNumberFills, doc.c_str());
        shape = py::make_tuple(static_cast<int>(D::RowsAtCompileTime));
      } else {
        constexpr int rows = D::RowsAtCompileTime, cols = D::ColsAtCompileTime;
        if constexpr (rows > 0 && rows == cols) {
          if (s.flags & kDiagonal) matrix_or_diagonal(s.name, s.member, doc.c_str());
          else dynamic(s.name, s.member, doc.c_str());
        } else {
          dynamic(s.name, s.member, doc.c_str());
        }
        if constexpr (rows > 0 && cols > 0) shape = py::make_tuple(rows, cols);
      }
    } else {
      value(s.name, s.member, doc.c_str());
    }
    py::dict row;
    row["name"] = s.name;
    row["unit"] = s.unit;
    row["rule"] = rule;
    row["min"] = s.min;
    row["max"] = s.max;
    row["doc"] = s.doc;
    row["shape"] = shape;
    row["diagonal"] = (s.flags & kDiagonal) != 0;  // a square matrix also given as its diagonal
    row["required"] = (s.flags & kRequired) != 0;
    table.append(row);
  }

  /// A number, bool, enum (by value) or nested struct (a reference into this
  /// one). A value of the wrong type is a TypeError naming the field.
  template <typename D>
  void value(const char* name, D T::*member, const char* doc) {
    const auto set = [member](T& self, const typename ValueArg<D>::type& v, const std::string& q) {
      self.*member = checked<D>(v, q);
    };
    if constexpr (std::is_arithmetic_v<D> || std::is_enum_v<D>)
      field(name, [member](const T& self) { return self.*member; }, set, doc);
    else
      field(name, [member](T& self) -> D& { return self.*member; }, set, doc);
  }

  /// A fixed-size vector: a writable numpy view (the storage is inside the
  /// struct); assigned from any real array-like of its length or, when
  /// `fills`, from one number for every entry.
  template <int N>
  void vector(const char* name, Eigen::Matrix<double, N, 1> T::*member, bool fills, const char* doc) {
    const auto get = [member](T& self) -> Eigen::Matrix<double, N, 1>& { return self.*member; };
    if (!fills) {
      field(name, get, [member](T& self, const typed::ArrayLike& v, const std::string& q) {
        self.*member = py_args::vector<N>(v, py_args::field(q), false);
      }, doc);
      return;
    }
    field(name, get, [member](T& self, const typed::RealOrArrayLike& v, const std::string& q) {
      if (py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v))
        (self.*member).setConstant(checked<double>(v, q));
      else
        self.*member = py_args::vector<N>(v, py_args::field(q), false);
    }, doc);
  }

  /// A fixed-size square matrix: a writable numpy view; assigned from an
  /// (N, N) array-like or its diagonal (N,).
  template <int N>
  void matrix_or_diagonal(const char* name, Eigen::Matrix<double, N, N> T::*member, const char* doc) {
    field(name, [member](T& self) -> Eigen::Matrix<double, N, N>& { return self.*member; },
          [member](T& self, const typed::ArrayLike& v, const std::string& q) {
            self.*member = py_args::matrix_or_diagonal<N>(v, q.c_str());
          }, doc);
  }

  /// A dynamic vector or matrix: a read-only copy (a view could outlive a
  /// buffer that a later assignment frees); assigned whole.
  template <typename M>
  void dynamic(const char* name, M T::*member, const char* doc) {
    field(
        name,
        [member](const T& self) {
          py::array a = py::cast(M(self.*member));
          a.attr("setflags")(py::arg("write") = false);
          return py::reinterpret_borrow<py::array_t<double>>(a);
        },
        [member](T& self, const typed::ArrayLike& v, const std::string& q) {
          if constexpr (M::ColsAtCompileTime == 1)
            self.*member = py_args::dynamic_vector(v, py_args::field(q), M::RowsAtCompileTime, false);
          else
            self.*member = py_args::dynamic_matrix(v, py_args::field(q), M::RowsAtCompileTime,
                                                   M::ColsAtCompileTime, false);
        },
        doc);
  }

  /// A list of bound structs: a tuple of copies (changing one changes the
  /// copy, not the struct); assigned whole from any sequence of E.
  template <typename E>
  void list(const char* name, std::vector<E> T::*member, const char* doc) {
    field(
        name,
        [member](const T& self) {
          py::typing::Tuple<E, py::ellipsis> out((self.*member).size());
          for (std::size_t i = 0; i < (self.*member).size(); ++i) out[i] = py::cast((self.*member)[i]);
          return out;
        },
        [member](T& self, const typed::IterableOf<E>& v, const std::string& q) {
          if (py::isinstance<py::str>(v) || !py::isinstance<py::sequence>(v))
            throw py::type_error(q + " must be a list of " + bound_name<E>() + ", got " + py_args::type_name(v));
          std::vector<E> items;
          for (const py::handle item : v) {
            if (!py::isinstance<E>(item))
              throw py::type_error(q + "[" + std::to_string(items.size()) + "] must be a " + bound_name<E>() +
                                   ", got " + py_args::type_name(item));
            items.push_back(item.cast<E>());
          }
          self.*member = std::move(items);
        },
        doc);
  }

  /// An optional bound struct or fixed-size vector: None when empty. The
  /// getter gives the held value itself (changing its fields changes this
  /// object's); assigning None empties it.
  template <typename D>
  void optional(const char* name, std::optional<D> T::*member, const char* doc) {
    field(
        name,
        [member](py::object self) -> py::typing::Optional<D> {
          auto& o = self.cast<T&>().*member;
          if (!o) return py::none();
          return py::cast(&*o, py::return_value_policy::reference_internal, self);
        },
        [member](T& self, const typename OptionalArg<D>::type& v, const std::string& q) {
          if (v.is_none()) {
            (self.*member).reset();
          } else if constexpr (std::is_base_of_v<Eigen::MatrixBase<D>, D>) {
            self.*member = D(py_args::vector<D::RowsAtCompileTime>(v, py_args::field(q), false));
          } else {
            self.*member = checked<D>(v, q);
          }
        },
        doc);
  }

  /// The Python name of a bound struct or enum (py::enum_ types have no
  /// py::type::of in pybind11 3).
  template <typename D>
  static std::string bound_name() {
    return py::str(py::detail::get_type_handle(typeid(D), true).attr("__name__"));
  }

  /// v as a D: a bool only from a bool, an integer only from an int, a real
  /// number from an int or float, a bound type only from itself.
  template <typename D>
  static D checked(const py::object& v, const std::string& name) {
    const auto got = [&] { return py_args::type_name(v); };
    if constexpr (std::is_same_v<D, bool>) {
      if (!py::isinstance<py::bool_>(v) && got() != "bool_")
        throw py::type_error(name + " must be a bool, got " + got());
      return v.cast<bool>();
    } else if constexpr (std::is_integral_v<D>) {
      return py_args::integer<D>(v, name);
    } else if constexpr (std::is_floating_point_v<D>) {
      return static_cast<D>(py_args::scalar(v, py_args::field(name), false));
    } else {
      if (!py::isinstance(v, py::detail::get_type_handle(typeid(D), true)))
        throw py::type_error(name + " must be a " + bound_name<D>() + ", got " + got());
      return v.cast<D>();
    }
  }

  /// The declared type of a value field's setter.
  template <typename D, typename = void>
  struct ValueArg {
    using type = typed::Of<D>;  // a bound struct or enum
  };
  template <typename D>
  struct ValueArg<D, std::enable_if_t<std::is_arithmetic_v<D>>> {
    using type = std::conditional_t<
        std::is_same_v<D, bool>, typed::Bool,
        std::conditional_t<std::is_integral_v<D>, typed::Index, typed::Real>>;
  };
  template <typename D>
  struct OptionalArg {
    using type = std::conditional_t<std::is_base_of_v<Eigen::MatrixBase<D>, D>,
                                    typed::OptionalArrayLike, typed::OptionalOf<D>>;
  };
  /// The second parameter of a field's setter `set(self, value, name)`.
  template <typename F>
  struct SetterArg;
  template <typename C, typename R, typename S, typename V, typename N>
  struct SetterArg<R (C::*)(S, V, N) const> {
    using type = std::decay_t<V>;
  };

  static std::string joined(const std::vector<std::string>& names) {
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
    return s;
  }

  /// Sets the fields named in `kw` through their Python setters.
  static void assign(T& obj, const py::dict& kw, const std::vector<std::string>& names,
                     const std::string& type) {
    py::object view = py::cast(&obj, py::return_value_policy::reference);
    for (const auto& item : kw) {
      const auto key = py::str(item.first).cast<std::string>();
      bool known = false;
      for (const auto& n : names) known = known || n == key;
      // The fields listed, no did-you-mean: the compiled module imports
      // nothing of the package (neurov.schema.did_you_mean is the readers').
      if (!known) {
        throw py::type_error(type + "() got an unexpected keyword argument '" + key +
                             "'; the fields are " + joined(names));
      }
      view.attr(item.first) = item.second;
    }
  }

  py::class_<T> cls_;  // a handle: copies name the one Python class
  std::string type_;
  std::shared_ptr<std::vector<std::string>> names_;
};

}  // namespace neurov::bindings
