// Catalog references (read_context.hpp): the scenario's CatalogLocations searched for a Catalog of
// the referenced name, its entry found by name, the entry's parameters declared with the
// reference's ParameterAssignments in place of their defaults.

#include <fmt/format.h>

#include <algorithm>
#include <system_error>

#include "read_context.hpp"

namespace emrm::openscenario::detail {
namespace {

// Reads every .xosc file in the catalog directories once, keeping the catalogs they hold by name;
// a catalog is also found by its file's name (esmini looks for CATALOGNAME.xosc), unless another
// catalog has that name.
void load_catalogs(Catalogs& catalogs) {
  if (!catalogs.loaded.empty()) return;
  std::vector<std::pair<std::string, xml::Element>> by_file;
  for (const auto& [location, dir] : catalogs.directories) {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) continue;
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
      if (entry.path().extension() == ".xosc") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
      const xml::Document document = xml::Document::load(file);
      xml::validate(document, xml::Schema::kOpenScenario);
      for (const xml::Element& catalog : document.root().children("Catalog")) {
        CatalogEntries& entries = catalogs.loaded[catalog.required("name")];
        for (const xml::Element& entry : catalog.children())
          if (const auto name = entry.attribute("name")) entries.entries.emplace(*name, entry);
        by_file.emplace_back(file.stem().string(), catalog);
      }
    }
  }
  for (const auto& [stem, catalog] : by_file) {
    if (catalogs.loaded.contains(stem) && catalog.required("name") != stem) continue;
    CatalogEntries& entries = catalogs.loaded[stem];
    for (const xml::Element& entry : catalog.children())
      if (const auto name = entry.attribute("name")) entries.entries.emplace(*name, entry);
  }
}

// The parameter a ParameterAssignment names. esmini drops a leading '$' (its samples write
// parameterRef="$Sloppiness"), so a reference written as a parameter's use names it too.
// The name is read as written: "$Sloppiness" is no use of the outer scope's parameter.
std::string parameter_ref(const xml::Element& assignment) {
  const std::string name = assignment.required("parameterRef");
  return name.starts_with('$') ? name.substr(1) : name;
}

}  // namespace

CatalogEntry resolve_catalog_reference(const xml::Element& reference, const ReadContext& context) {
  const std::string catalog_name = context.text(reference, "catalogName");
  const std::string entry_name = context.text(reference, "entryName");
  load_catalogs(context.catalogs());
  const auto catalog = context.catalogs().loaded.find(catalog_name);
  if (catalog == context.catalogs().loaded.end()) {
    std::string dirs;
    for (const auto& [location, dir] : context.catalogs().directories) {
      std::error_code ec;
      // esmini falls back on its own installation's resources/xosc/Catalogs; emrm reads only what
      // the scenario names, so a missing directory is said.
      dirs += (dirs.empty() ? "" : ", ") +
              fmt::format("{} {}{}", location, dir.string(),
                          std::filesystem::is_directory(dir, ec) ? "" : " (no such directory)");
    }
    reference.fail("catalogName", fmt::format("catalogName: no catalog named '{}' in the CatalogLocations ({})",
                                              catalog_name, dirs.empty() ? "none declared" : dirs));
  }
  const auto entry = catalog->second.entries.find(entry_name);
  if (entry == catalog->second.entries.end()) {
    std::string names;
    for (const auto& [name, element] : catalog->second.entries) names += (names.empty() ? "" : ", ") + name;
    reference.fail("entryName", fmt::format("entryName: catalog '{}' has no entry '{}' (entries: {})", catalog_name,
                                            entry_name, names));
  }
  ParameterOverrides assigned;
  if (const auto assignments = reference.child("ParameterAssignments"))
    for (const xml::Element& a : assignments->children("ParameterAssignment"))
      assigned[parameter_ref(a)] = context.text(a, "value");
  CatalogEntry out{entry->second, std::make_unique<ParameterScope>(&context.scope())};
  declare_parameters(entry->second, *out.scope, context, assigned);
  if (const auto assignments = reference.child("ParameterAssignments"))
    for (const xml::Element& a : assignments->children("ParameterAssignment")) {
      const std::string name = parameter_ref(a);
      const auto& declared = out.scope->declared();
      if (std::none_of(declared.begin(), declared.end(), [&](const Parameter& p) { return p.name == name; }))
        a.fail("parameterRef", fmt::format("parameterRef: entry '{}' of catalog '{}' declares no parameter '{}'",
                                           entry_name, catalog_name, name));
    }
  return out;
}

}  // namespace emrm::openscenario::detail
