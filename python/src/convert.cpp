// Conversions shared by the parts of the module: JSON values, paths, mappings given for files.

#include <cmath>
#include <cstdint>

#include "bindings.hpp"

namespace emrm::python {
namespace {

template <class Json>
py::object json_to_python(const Json& j) {
  using Type = nlohmann::json::value_t;
  switch (j.type()) {
    case Type::boolean:
      return py::bool_(j.template get<bool>());
    case Type::number_integer:
      return py::int_(j.template get<std::int64_t>());
    case Type::number_unsigned:
      return py::int_(j.template get<std::uint64_t>());
    case Type::number_float: {
      const double v = j.template get<double>();
      return std::isfinite(v) ? py::object(py::float_(v)) : py::object(py::none());
    }
    case Type::string:
      return py::str(j.template get_ref<const std::string&>());
    case Type::array: {
      py::list list;
      for (const auto& item : j) list.append(json_to_python(item));
      return list;
    }
    case Type::object: {
      py::dict dict;
      for (auto it = j.begin(); it != j.end(); ++it) dict[py::str(it.key())] = json_to_python(it.value());
      return dict;
    }
    case Type::null:
    case Type::binary:
    case Type::discarded:
      break;
  }
  return py::none();
}

// json.dumps's `default`: what JSON has no type for. NumPy numbers become Python numbers, paths strings.
py::object json_default(py::handle value) {
  if (py::hasattr(value, "item")) return value.attr("item")();
  if (py::isinstance(value, py::module_::import("os").attr("PathLike"))) return py::str(to_path(value).string());
  throw py::type_error("emrm: a value of type " + py::str(py::type::of(value).attr("__name__")).cast<std::string>() +
                       " cannot stand in a scene, campaign or ODD");
}

}  // namespace

std::string mapping_text(py::handle mapping) {
  if (!py::isinstance<py::dict>(mapping) &&
      !py::isinstance(mapping, py::module_::import("collections.abc").attr("Mapping")))
    throw py::type_error("emrm: expected a file name or a mapping (dict), got " +
                         py::str(py::type::of(mapping).attr("__name__")).cast<std::string>());
  return py::module_::import("json")
      .attr("dumps")(py::dict(py::reinterpret_borrow<py::object>(mapping)), py::arg("indent") = 2,
                     py::arg("default") = py::cpp_function(json_default))
      .cast<std::string>();
}

py::object to_python(const nlohmann::json& j) { return json_to_python(j); }
py::object to_python(const nlohmann::ordered_json& j) { return json_to_python(j); }

bool is_path(py::handle value) {
  return py::isinstance<py::str>(value) || py::isinstance(value, py::module_::import("os").attr("PathLike"));
}

std::filesystem::path to_path(py::handle path) {
  return std::filesystem::path(py::module_::import("os").attr("fspath")(path).cast<std::string>());
}

}  // namespace emrm::python
