// The extension module `_emrm` of the Python package emrm (docs/python.md). python/emrm/__init__.py
// re-exports it and adds what is plain Python: the pandas tables, temporary folders, the wrappers'
// signatures.

#include "bindings.hpp"
#include "emrm/openscenario/family.hpp"
#include "emrm/version.hpp"

PYBIND11_MODULE(_emrm, m) {
  m.doc() = "The compiled half of the emrm package: the same C++ library as the emrm command line.";
  m.attr("__version__") = emrm::kVersion;
  // Imported OpenSCENARIO scenarios (docs/import.md): their family, and scene files ending in .xosc.
  static const emrm::openscenario::Registration openscenario_family;
  emrm::python::bind_errors(m);
  emrm::python::bind_config(m);
  emrm::python::bind_simulate(m);
  emrm::python::bind_campaign(m);
  emrm::python::bind_scenario(m);
  emrm::python::bind_analysis(m);
}
