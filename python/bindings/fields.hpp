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
// the C++ validator. A struct described by config_fields
// (neurov/core/field_spec.hpp) is bound whole by Fields<T>::described.
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
  Fields(py::class_<T> cls, std::string type_name)
      : cls_(std::move(cls)),
        type_(std::move(type_name)),
        names_(std::make_shared<std::vector<std::string>>()) {}
  /// Binds T as `name` in `m`, its fields to follow.
  Fields(py::module_& m, const char* name, const char* doc)
      : Fields(py::class_<T>(m, name, doc), name) {}

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

  /// A number, bool, enum (by value) or nested struct (a reference into this
  /// one). A value of the wrong type is a TypeError naming the field.
  template <typename D>
  Fields& value(const char* name, D T::*member, const char* doc) {
    const std::string qualified = type_ + "." + name;
    auto set = [member, qualified](T& self, const typename ValueArg<D>::type& v) {
      self.*member = checked<D>(v, qualified);
    };
    if constexpr (std::is_arithmetic_v<D> || std::is_enum_v<D>)
      cls_.def_property(name, [member](const T& self) { return self.*member; }, set, doc);
    else
      cls_.def_property(name, [member](T& self) -> D& { return self.*member; }, set, doc);
    names_->push_back(name);
    return *this;
  }

  /// A fixed-size vector: a writable numpy view; assigned from any real
  /// array-like of the right length.
  template <int N>
  Fields& vector(const char* name, Eigen::Matrix<double, N, 1> T::*member, const char* doc) {
    const std::string qualified = type_ + "." + name;
    cls_.def_property(
        name, [member](T& self) -> Eigen::Matrix<double, N, 1>& { return self.*member; },
        [member, qualified](T& self, const typed::ArrayLike& v) {
          auto a = shaped(v, qualified, 1, N, -1);
          self.*member = Eigen::Map<const Eigen::Matrix<double, N, 1>>(a.data());
        },
        doc);
    names_->push_back(name);
    return *this;
  }

  /// A fixed-size vector that also takes one number, which fills every entry.
  template <int N>
  Fields& vector_or_number(const char* name, Eigen::Matrix<double, N, 1> T::*member,
                           const char* doc) {
    return field(
        name, [member](T& self) -> Eigen::Matrix<double, N, 1>& { return self.*member; },
        [member](T& self, const typed::RealOrArrayLike& v, const std::string& qualified) {
          if (py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v))
            (self.*member).setConstant(checked<double>(py::reinterpret_borrow<py::object>(v),
                                                       qualified));
          else
            self.*member = Eigen::Map<const Eigen::Matrix<double, N, 1>>(
                shaped(v, qualified, 1, N, -1).data());
        },
        doc);
  }

  /// A fixed-size square matrix: a writable numpy view; assigned from an
  /// (N, N) array-like or its diagonal (N,).
  template <int N>
  Fields& matrix_or_diagonal(const char* name, Eigen::Matrix<double, N, N> T::*member,
                             const char* doc) {
    return field(
        name, [member](T& self) -> Eigen::Matrix<double, N, N>& { return self.*member; },
        [member](T& self, const typed::ArrayLike& v, const std::string& qualified) {
          self.*member = py_args::matrix_or_diagonal<N>(v, qualified.c_str());
        },
        doc);
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

  /// A dynamic vector: a read-only copy; assigned whole.
  template <typename M>
  Fields& dynamic_vector(const char* name, M T::*member, const char* doc) {
    return dynamic(name, member, 1, -1, -1, doc);
  }

  /// A dynamic matrix (rows or cols < 0: any): a read-only copy; assigned whole.
  template <typename M>
  Fields& dynamic_matrix(const char* name, M T::*member, py::ssize_t rows, py::ssize_t cols,
                         const char* doc) {
    return dynamic(name, member, 2, rows, cols, doc);
  }

  /// A list of bound structs: a tuple of copies (changing one changes the
  /// copy, not the struct); assigned whole from any sequence of E.
  template <typename E>
  Fields& list(const char* name, std::vector<E> T::*member, const char* element,
               const char* doc) {
    const std::string qualified = type_ + "." + name;
    const std::string element_name = element;
    cls_.def_property(
        name,
        [member](const T& self) {
          py::typing::Tuple<E, py::ellipsis> out((self.*member).size());
          for (std::size_t i = 0; i < (self.*member).size(); ++i)
            out[i] = py::cast((self.*member)[i]);
          return out;
        },
        [member, qualified, element_name](T& self, const typed::IterableOf<E>& v) {
          if (py::isinstance<py::str>(v) || !py::isinstance<py::sequence>(v))
            throw py::type_error(qualified + " must be a list of " + element_name + ", got " +
                                 type_name(v));
          std::vector<E> items;
          std::size_t i = 0;
          for (const py::handle item : v) {
            if (!py::isinstance<E>(item))
              throw py::type_error(qualified + "[" + std::to_string(i) + "] must be a " +
                                   element_name + ", got " + type_name(item));
            items.push_back(item.cast<E>());
            ++i;
          }
          self.*member = std::move(items);
        },
        doc);
    names_->push_back(name);
    return *this;
  }

  /// The keyword constructor, repr, copy and pickle; call after the fields.
  /// An optional bound struct or fixed-size vector: None when empty. The
  /// getter gives the held value itself (changing its fields changes this
  /// object's); assigning None empties it.
  template <typename D>
  Fields& optional(const char* name, std::optional<D> T::*member, const char* doc) {
    const std::string qualified = type_ + "." + name;
    cls_.def_property(
        name,
        [member](py::object self) -> py::typing::Optional<D> {
          auto& o = self.cast<T&>().*member;
          if (!o) return py::none();
          return py::cast(&*o, py::return_value_policy::reference_internal, self);
        },
        [member, qualified](T& self, const typename OptionalArg<D>::type& v) {
          if (v.is_none()) {
            (self.*member).reset();
          } else if constexpr (std::is_base_of_v<Eigen::MatrixBase<D>, D>) {
            auto a = shaped(v, qualified, 1, D::RowsAtCompileTime, -1);
            self.*member = D(Eigen::Map<const D>(a.data()));
          } else {
            self.*member = checked<D>(v, qualified);
          }
        },
        doc);
    names_->push_back(name);
    return *this;
  }

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
      using E = typename FieldKind<D>::Element;
      const py::handle type = py::detail::get_type_handle(typeid(E), true);
      const std::string element = py::str(type.attr("__name__"));
      list(s.name, s.member, element.c_str(), doc.c_str());
    } else if constexpr (FieldKind<D>::kind == 1) {
      if constexpr (D::RowsAtCompileTime > 0 && D::ColsAtCompileTime == 1) {
        if (s.flags & kNumberFills)
          vector_or_number(s.name, s.member, doc.c_str());
        else
          vector(s.name, s.member, doc.c_str());
        shape = py::make_tuple(static_cast<int>(D::RowsAtCompileTime));
      } else if constexpr (D::ColsAtCompileTime == 1) {
        dynamic_vector(s.name, s.member, doc.c_str());
      } else {
        constexpr int rows = D::RowsAtCompileTime, cols = D::ColsAtCompileTime;
        if constexpr (rows > 0 && rows == cols) {
          if (s.flags & kDiagonal) matrix_or_diagonal(s.name, s.member, doc.c_str());
          else dynamic_matrix(s.name, s.member, rows, cols, doc.c_str());
        } else {
          dynamic_matrix(s.name, s.member, rows, cols, doc.c_str());
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

  template <typename M>
  Fields& dynamic(const char* name, M T::*member, int ndim, py::ssize_t rows, py::ssize_t cols,
                  const char* doc) {
    const std::string qualified = type_ + "." + name;
    cls_.def_property(
        name,
        [member](const T& self) {
          py::array a = py::cast(M(self.*member));
          a.attr("setflags")(py::arg("write") = false);
          return py::reinterpret_borrow<py::array_t<double>>(a);
        },
        [member, qualified, ndim, rows, cols](T& self, const typed::ArrayLike& v) {
          auto a = shaped(v, qualified, ndim, rows, cols);
          if constexpr (M::ColsAtCompileTime == 1)
            self.*member = Eigen::Map<const Eigen::VectorXd>(a.data(), a.shape(0));
          else
            self.*member =
                Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic,
                                               Eigen::RowMajor>>(a.data(), a.shape(0), a.shape(1));
        },
        doc);
    names_->push_back(name);
    return *this;
  }

  /// v as a real array with ndim dimensions of the given sizes (< 0: any);
  /// TypeError or ValueError naming the field.
  static py::array_t<double, py::array::c_style> shaped(const py::handle& v,
                                                        const std::string& name, int ndim,
                                                        py::ssize_t rows, py::ssize_t cols) {
    const auto size = [](py::ssize_t n, const char* any) {
      return n < 0 ? std::string(any) : std::to_string(n);
    };
    const std::string expected = ndim == 1 ? "(" + size(rows, "n") + ",)"
                                           : "(" + size(rows, "n") + ", " + size(cols, "m") + ")";
    auto a = py_args::real_array(v, name.c_str(), expected);
    const bool ok = a.ndim() == ndim && (rows < 0 || a.shape(0) == rows) &&
                    (ndim == 1 || cols < 0 || a.shape(1) == cols);
    if (!ok)
      throw py::value_error(name + " must have shape " + expected + ", got " +
                            py_args::shape_string(a));
    return a;
  }

  /// v as a D: a bool only from a bool, an integer only from an int, a real
  /// number from an int or float, a bound type only from itself.
  template <typename D>
  static D checked(const py::object& v, const std::string& name) {
    const auto got = [&] { return type_name(v); };
    if constexpr (std::is_same_v<D, bool>) {
      if (!py::isinstance<py::bool_>(v) && got() != "bool_")
        throw py::type_error(name + " must be a bool, got " + got());
      return v.cast<bool>();
    } else if constexpr (std::is_integral_v<D>) {
      return py_args::integer<D>(v, name);
    } else if constexpr (std::is_floating_point_v<D>) {
      if (py::isinstance<py::bool_>(v) || !py::hasattr(v, "__float__") ||
          (py::isinstance<py::array>(v) && py::reinterpret_borrow<py::array>(v).ndim() != 0))
        throw py::type_error(name + " must be a real number, got " + got());
      return v.cast<D>();
    } else {
      // A bound struct or enum (py::enum_ types have no py::type::of in pybind11 3).
      const py::handle type = py::detail::get_type_handle(typeid(D), true);
      if (!py::isinstance(v, type))
        throw py::type_error(name + " must be a " + std::string(py::str(type.attr("__name__"))) +
                             ", got " + got());
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

  static std::string type_name(const py::handle& v) {
    return std::string(py::str(py::type::handle_of(v).attr("__name__")));
  }

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
