// The safety-case analysis (`emrm analyze`, docs/safety-yaml.md) and the FSM checks (`emrm fsm`,
// docs/fsm.md), each produced by the library's own functions: findings, traceability and ASIL rows
// as their files hold them, the JSON and text as the commands print them.

#include "emrm/safety/analysis.hpp"

#include <pybind11/stl.h>

#include <optional>

#include "bindings.hpp"
#include "emrm/core/text.hpp"
#include "emrm/fsm/load.hpp"
#include "emrm/fsm/report.hpp"
#include "emrm/workflow/safety_case.hpp"

namespace emrm::python {
namespace {

// A table as its CSV file has it: the header, then the rows (text).
py::dict table(const core::Row& header, const std::vector<core::Row>& rows) {
  py::dict columns;
  for (std::size_t c = 0; c < header.size(); ++c) {
    py::list values;
    for (const auto& row : rows) values.append(row[c]);
    columns[py::str(header[c])] = values;
  }
  return columns;
}

safety::Analysis analyze(py::handle safety_file, py::handle fsm_file, bool no_fsm) {
  std::optional<std::filesystem::path> fsm;
  if (!fsm_file.is_none()) fsm = to_path(fsm_file);
  return workflow::analyze_safety_file(to_path(safety_file), fsm, no_fsm);
}

fsm::Report check_fsm(py::handle file, bool check, int words, const std::vector<std::string>& word_queries,
                      py::handle traces, py::handle compose, std::size_t max_states) {
  const std::filesystem::path path = to_path(file);
  fsm::Generator g = fsm::load_generator(path);
  std::string source = path.string();
  if (!compose.is_none()) {
    const std::filesystem::path other = to_path(compose);
    g = fsm::compose(g, fsm::load_generator(other), max_states);
    source += " || " + other.string();
  }
  fsm::ReportRequest request;
  request.check = check;
  request.words_max_length = words;
  request.word_queries = word_queries;
  if (!traces.is_none()) {
    const std::filesystem::path trace_file = to_path(traces);
    request.traces = fsm::TraceFile{trace_file.string(), fsm::load_traces(trace_file)};
  }
  return fsm::make_report(std::move(g), std::move(source), request);
}

}  // namespace

void bind_analysis(py::module_& m) {
  py::class_<safety::Analysis> analysis(m, "_Analysis", "A checked safety case (emrm.analyze wraps it).");
  analysis.def_property_readonly("errors", &safety::Analysis::errors);
  analysis.def_property_readonly("warnings", &safety::Analysis::warnings);
  analysis.def_property_readonly(
      "findings", [](const safety::Analysis& a) { return to_python(safety::findings_json(a.findings)); });
  analysis.def_property_readonly("traceability", [](const safety::Analysis& a) {
    std::vector<core::Row> rows;
    for (const auto& row : a.matrix) rows.push_back(safety::to_row(row));
    return table(safety::traceability_header(), rows);
  });
  analysis.def_property_readonly(
      "asil", [](const safety::Analysis& a) { return table(safety::asil_header(), safety::asil_rows(a.safety_case)); });
  analysis.def("to_dict", [](const safety::Analysis& a) { return to_python(safety::to_json(a)); });
  analysis.def("to_text", [](const safety::Analysis& a) { return safety::to_text(a); });
  analysis.def("write", [](const safety::Analysis& a, py::handle dir) {
    std::vector<std::string> written;
    for (const auto& p : safety::write_analysis(to_path(dir), a)) written.push_back(p.string());
    return written;
  });
  m.def("_analyze", &analyze, py::arg("safety"), py::arg("fsm"), py::arg("no_fsm"));

  py::class_<fsm::Report> report(
      m, "FsmReport",
      "What `emrm fsm` reports about one machine: ok (no check failed, every trace in L(G)), to_dict() (the\n"
      "JSON of --format json), to_text() (what it prints), dot() (the diagram, edges counted by the traces).");
  report.def_property_readonly("ok", &fsm::Report::ok);
  report.def("to_dict", [](const fsm::Report& r) { return to_python(fsm::to_json(r)); });
  report.def("to_text", [](const fsm::Report& r) { return fsm::to_text(r); });
  report.def("dot", [](const fsm::Report& r) { return fsm::diagram_dot(r); });
  report.def("__repr__", [](const fsm::Report& r) {
    return "FsmReport(" + r.source + ", ok=" + (r.ok() ? "True" : "False") + ")";
  });
  m.def("check_fsm", &check_fsm, py::arg("path"), py::kw_only(), py::arg("check") = true, py::arg("words") = -1,
        py::arg("word") = std::vector<std::string>{}, py::arg("traces") = py::none(), py::arg("compose") = py::none(),
        py::arg("max_states") = fsm::kDefaultMaxComposedStates,
        "Checks a hazard-loss FSM as `emrm fsm PATH --check` does (docs/fsm.md): accessible, co-accessible,\n"
        "deterministic, non-blocking. words=N lists L(G) up to N events; word=['e1 e2', ...] looks words up;\n"
        "traces=FILE measures transition coverage; compose=OTHER works on G || OTHER. Returns an FsmReport.");
}

}  // namespace emrm::python
