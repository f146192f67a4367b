#pragma once

// The extension module `_emrm` (docs/python.md): each file adds one part of the library to it. The
// module only converts arguments and results; every number comes from the library the command line
// calls, through the same functions.

#include <pybind11/pybind11.h>

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "emrm/core/error.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::python {

namespace py = pybind11;

/// emrm.InputError, emrm.UsageError, emrm.Error, emrm.Interrupted, and the translation of the
/// library's exceptions into them (errors.cpp).
void bind_errors(py::module_& m);
/// emrm.Scene and its parts (config.cpp).
void bind_config(py::module_& m);
/// emrm.simulate and its result (simulate.cpp).
void bind_simulate(py::module_& m);
/// Sweeps and results stores (campaign.cpp).
void bind_campaign(py::module_& m);
/// Covering arrays and the minimum scenario set (scenario.cpp).
void bind_scenario(py::module_& m);
/// The safety-case analysis and the FSM checks (analysis.cpp).
void bind_analysis(py::module_& m);

// ---- conversions shared by the parts (convert.cpp) -------------------------------------------

/// A JSON value as Python objects: objects as dicts (in their order), arrays as lists; a number that
/// is not finite as None, as nlohmann's dump() writes it (null).
[[nodiscard]] py::object to_python(const nlohmann::json& j);
[[nodiscard]] py::object to_python(const nlohmann::ordered_json& j);

/// A str or os.PathLike as a path.
[[nodiscard]] std::filesystem::path to_path(py::handle path);

/// True for a str or an os.PathLike (a file name), false for anything else (a dict).
[[nodiscard]] bool is_path(py::handle value);

/// Raises the emrm.InputError that `error` becomes (errors.cpp), with the line of `text` it points
/// at added as a note (PEP 678): throws py::error_already_set.
[[noreturn]] void raise_input_error_in(const InputError& error, const std::string& text);

/// A Python mapping given in place of a YAML file (a scene, a campaign, an ODD) as the text the
/// library's loaders read: JSON with one key a line, which is YAML too. NumPy numbers are written as
/// numbers, paths as strings.
[[nodiscard]] std::string mapping_text(py::handle mapping);

/// Loads a mapping given in place of a file: `parse(mapping_text(mapping))`. An InputError it
/// throws is raised with the offending line of that text as a note.
template <class Parse>
auto parse_mapping(py::handle mapping, Parse parse) -> decltype(parse(std::string())) {
  const std::string text = mapping_text(mapping);
  try {
    return parse(text);
  } catch (const InputError& e) {
    raise_input_error_in(e, text);
  }
}

/// The scene a function is given: an emrm.Scene, a scene file, a mapping, or None for the built-in
/// scene (shared, never copied).
[[nodiscard]] std::shared_ptr<const sim::SceneConfig> scene_from(py::handle scene);

}  // namespace emrm::python
