#include "emrm/safety/traceability.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <type_traits>

#include "emrm/core/json_archive.hpp"
#include "emrm/safety/asil.hpp"

namespace emrm::safety {
namespace {

std::size_t loss_rank(const SafetyCase& sc, const std::string& id) {
  for (std::size_t i = 0; i < sc.losses.size(); ++i)
    if (sc.losses[i].id == id) return i;
  return 0;
}

std::string stated_or_empty(const std::optional<std::string>& s) { return s.value_or(""); }

template <class E>
std::string name_or_empty(const std::optional<E>& e) {
  return e ? std::string(core::enum_name(*e)) : std::string();
}

}  // namespace

std::vector<MappingEntry> map_hara_stpa(const SafetyCase& sc) {
  std::vector<MappingEntry> out;
  for (const auto& u : sc.ucas) {
    MappingEntry entry{u.id, {}, {}, {}};
    for (const auto& ref : u.hazards) {
      const Hazard* h = sc.find_hazard(ref.id);
      if (!h) continue;
      entry.hazards.push_back(h->id);
      entry.risk.asil = std::max(entry.risk.asil, determine_asil(*h));
      for (const auto& lref : h->losses) {
        const Loss* l = sc.find_loss(lref.id);
        if (!l || std::find(entry.losses.begin(), entry.losses.end(), l->id) != entry.losses.end()) continue;
        entry.losses.push_back(l->id);
        entry.risk.irreversible = entry.risk.irreversible || !l->reversible;
      }
    }
    std::sort(entry.losses.begin(), entry.losses.end(),
              [&](const std::string& a, const std::string& b) { return loss_rank(sc, a) < loss_rank(sc, b); });
    if (!entry.losses.empty()) entry.risk.worst_loss = entry.losses.back();
    out.push_back(std::move(entry));
  }
  return out;
}

std::vector<TraceRow> traceability_matrix(const SafetyCase& sc) {
  std::vector<TraceRow> rows;
  for (const auto& u : sc.ucas) {
    std::vector<std::string> transitions;
    for (const auto& t : u.fsm_transitions) transitions.push_back(t.str());
    for (const auto& href : u.hazards) {
      const Hazard* h = sc.find_hazard(href.id);
      if (!h) continue;
      for (const auto& lref : h->losses) {
        const Loss* l = sc.find_loss(lref.id);
        if (!l) continue;
        TraceRow row;
        row.uca = u.id;
        row.uca_type = core::enum_name(u.type);
        row.control_action = u.control_action.id;
        row.hazard = h->id;
        row.asil = core::enum_name(determine_asil(*h));
        row.smil = stated_or_empty(h->smil);
        row.loss = l->id;
        row.loss_name = l->name;
        row.loss_reversible = l->reversible;
        row.transitions = transitions;
        row.region = u.region.value_or("");
        rows.push_back(std::move(row));
      }
    }
  }
  return rows;
}

core::Row traceability_header() {
  core::Row header;
  const TraceRow none;
  TraceRow::visit_fields(none, [&](const char* column, const auto&, auto...) { header.emplace_back(column); });
  return header;
}

core::Row to_row(const TraceRow& r) {
  core::Row row;
  TraceRow::visit_fields(r, [&](const char*, const auto& field, auto... separator) {
    using T = std::remove_cvref_t<decltype(field)>;
    if constexpr (std::is_same_v<T, bool>)
      row.emplace_back(field ? "yes" : "no");
    else if constexpr (sizeof...(separator) > 0)
      row.push_back(core::join(field, std::string(separator...)));
    else
      row.push_back(field);
  });
  return row;
}

std::vector<TraceRow> read_traceability_csv(const std::filesystem::path& path) {
  const std::string file = path.string();
  const auto records = core::parse_csv(core::read_input_file(path), file);
  const core::Row header = traceability_header();
  if (records.empty() || records.front().fields != header)
    throw InputError({file, 1, 1},
                     fmt::format("expected a traceability matrix with the header {}", core::join(header, ",")));
  std::vector<TraceRow> rows;
  for (std::size_t i = 1; i < records.size(); ++i) {
    const auto& record = records[i];
    core::check_row_length(record, header.size(), file);
    TraceRow r;
    std::size_t c = 0;
    TraceRow::visit_fields(r, [&](const char* column, auto& field, auto... separator) {
      using T = std::remove_cvref_t<decltype(field)>;
      const std::string& text = record.fields[c];
      const SourceLocation where{file, record.lines[c], record.columns[c]};
      ++c;
      if constexpr (std::is_same_v<T, bool>) {
        if (text != "yes" && text != "no")
          throw InputError(where, fmt::format("{}: expected yes or no, got '{}'", column, text.substr(0, 40)));
        field = text == "yes";
      } else if constexpr (sizeof...(separator) > 0) {
        // The items between the separators, without the blanks the separator puts before them.
        const char sep = std::string_view(separator...).front();
        field.clear();
        for (std::size_t from = 0; from <= text.size();) {
          const std::size_t to = std::min(text.find(sep, from), text.size());
          const std::size_t first = text.find_first_not_of(' ', from);
          if (first < to) field.push_back(text.substr(first, to - first));
          from = to + 1;
        }
      } else {
        field = text;
      }
    });
    rows.push_back(std::move(r));
  }
  return rows;
}

namespace {
std::vector<core::Row> rows_of(const std::vector<TraceRow>& rows) {
  std::vector<core::Row> out;
  out.reserve(rows.size());
  for (const auto& r : rows) out.push_back(to_row(r));
  return out;
}
}  // namespace

std::string traceability_csv(const std::vector<TraceRow>& rows) {
  return core::csv_table(traceability_header(), rows_of(rows));
}

std::string traceability_markdown(const std::vector<TraceRow>& rows) {
  // A reader's table: long scenario lists shortened to their count and first ids (the CSV has all).
  constexpr std::size_t kShown = 6;
  auto table = rows_of(rows);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& ids = rows[i].scenarios;
    if (ids.size() <= kShown) continue;
    table[i].back() = fmt::format("{}: {} …", ids.size(),
                                  core::join({ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(kShown)}, " "));
  }
  return core::markdown_table(traceability_header(), table);
}

std::vector<core::FileContent> traceability_files(const std::filesystem::path& dir, const std::string& case_name,
                                                  const std::vector<TraceRow>& rows) {
  return {{dir / kTraceabilityCsv, traceability_csv(rows)},
          {dir / kTraceabilityMd, "# Traceability matrix: " + case_name + "\n\n" + traceability_markdown(rows)}};
}

core::Row asil_header() {
  return {"hazard",          "severity",     "exposure",     "controllability", "asil",       "asil_stated",
          "maneuverability", "avoidability", "mitigability", "smil_table",      "smil_stated"};
}

std::vector<core::Row> asil_rows(const SafetyCase& sc) {
  std::vector<core::Row> rows;
  for (const auto& h : sc.hazards) {
    const SmilRule* rule = sc.smil ? find_smil_rule(*sc.smil, h) : nullptr;
    rows.push_back({h.id, std::string(core::enum_name(h.severity)), std::string(core::enum_name(h.exposure)),
                    std::string(core::enum_name(h.controllability)), std::string(core::enum_name(determine_asil(h))),
                    name_or_empty(h.asil), name_or_empty(h.maneuverability), name_or_empty(h.avoidability),
                    name_or_empty(h.mitigability), rule ? rule->smil : "", stated_or_empty(h.smil)});
  }
  return rows;
}

nlohmann::json findings_json(const std::vector<Finding>& findings) {
  auto out = nlohmann::json::array();
  for (const auto& f : findings) out.push_back(nlohmann::json(core::write_json(f)));  // members sorted by name
  return out;
}

std::vector<Finding> read_findings_json(const std::filesystem::path& path) {
  return core::read_json_file<std::vector<Finding>>(path);
}

nlohmann::json analysis_json(const SafetyCase& sc, const std::vector<Finding>& findings) {
  nlohmann::json j;
  j["file"] = sc.file;
  j["name"] = sc.name;
  j["summary"] = {{"losses", sc.losses.size()},
                  {"hazards", sc.hazards.size()},
                  {"control_actions", sc.control_actions.size()},
                  {"ucas", sc.ucas.size()},
                  {"errors", count(findings, FindingSeverity::kError)},
                  {"warnings", count(findings, FindingSeverity::kWarning)}};
  j["findings"] = findings_json(findings);

  const auto header = asil_header();
  auto asil = nlohmann::json::array();
  for (const auto& row : asil_rows(sc)) {
    nlohmann::json item;
    for (std::size_t i = 0; i < header.size(); ++i) item[header[i]] = row[i];
    asil.push_back(std::move(item));
  }
  j["asil"] = std::move(asil);

  auto mapping = nlohmann::json::array();
  for (const auto& m : map_hara_stpa(sc))
    mapping.push_back({{"uca", m.uca},
                       {"hazards", m.hazards},
                       {"losses", m.losses},
                       {"risk",
                        {{"asil", core::enum_name(m.risk.asil)},
                         {"worst_loss", m.risk.worst_loss},
                         {"irreversible", m.risk.irreversible}}}});
  j["mapping"] = std::move(mapping);

  auto matrix = nlohmann::json::array();
  for (const auto& r : traceability_matrix(sc))
    matrix.push_back({{"uca", r.uca},
                      {"uca_type", r.uca_type},
                      {"control_action", r.control_action},
                      {"hazard", r.hazard},
                      {"asil", r.asil},
                      {"smil", r.smil},
                      {"loss", r.loss},
                      {"loss_name", r.loss_name},
                      {"reversible", r.loss_reversible},
                      {"fsm_transitions", r.transitions},
                      {"region", r.region},
                      {"scenarios", r.scenarios}});
  j["traceability"] = std::move(matrix);
  return j;
}

}  // namespace emrm::safety
