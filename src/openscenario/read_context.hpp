#pragma once

// What the OpenSCENARIO reader's parts share (reader.cpp and read_*.cpp): the parameter scope an
// element is read in, the attribute readers that resolve parameters and check ranges, and the
// names a reference may name.

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <string_view>

#include "emrm/openscenario/scenario.hpp"
#include "emrm/xml/document.hpp"

namespace emrm::openscenario::detail {

/// A catalog: its entries by name, in the document that holds them.
struct CatalogEntries {
  std::map<std::string, xml::Element> entries;
};

/// The catalogs a scenario's CatalogLocations name, by catalog name (read on first use).
struct Catalogs {
  std::map<std::string, std::filesystem::path> directories;  ///< by location element (VehicleCatalog, ...)
  std::map<std::string, CatalogEntries> loaded;              ///< by catalog name
};

class ReadContext {
 public:
  ReadContext(const ParameterScope& scope, const std::filesystem::path& dir, Catalogs& catalogs,
              const std::set<std::string>& entities, const RoadAccess* roads)
      : scope_(scope), dir_(dir), catalogs_(catalogs), entities_(entities), roads_(roads) {}

  /// The same context with another scope (a catalog entry's).
  [[nodiscard]] ReadContext with(const ParameterScope& scope) const {
    ReadContext c(scope, dir_, catalogs_, entities_, roads_);
    c.elements_ = elements_;
    c.rev_minor = rev_minor;
    c.global_ = global_;
    c.uses_ = uses_;
    return c;
  }

  /// The attribute's text with parameters resolved; std::nullopt when absent.
  [[nodiscard]] std::optional<std::string> optional_text(const xml::Element& e, std::string_view name) const;
  /// The attribute's text with parameters resolved; InputError at the tag when absent.
  [[nodiscard]] std::string text(const xml::Element& e, std::string_view name) const;
  /// A number in [low, high] (a unit for messages); InputError at the attribute otherwise.
  [[nodiscard]] double number(const xml::Element& e, std::string_view name, std::string_view unit, double low = -1e12,
                              double high = 1e12) const;
  [[nodiscard]] std::optional<double> optional_number(const xml::Element& e, std::string_view name,
                                                      std::string_view unit, double low = -1e12,
                                                      double high = 1e12) const;
  [[nodiscard]] int integer(const xml::Element& e, std::string_view name, int low, int high) const;
  [[nodiscard]] bool boolean(const xml::Element& e, std::string_view name, bool fallback) const;
  /// One of `names` (as spelled in the XSD); the index.
  [[nodiscard]] std::size_t choice(const xml::Element& e, std::string_view name,
                                   std::initializer_list<std::string_view> names) const;

  /// An entityRef attribute naming an entity the scenario declares.
  [[nodiscard]] std::string entity_ref(const xml::Element& e, std::string_view name) const;

  /// The element's one child element (the chosen member of an XSD choice), checked against the
  /// supported table (supported.hpp) under `choice`.
  [[nodiscard]] xml::Element chosen(const xml::Element& e, std::string_view choice) const;

  /// Records in uses_ (without a unit) every global parameter `text` refers to ($name, also inside
  /// ${...}).
  void record_references(std::string_view text, const SourceLocation& where) const;
  /// The global parameter the attribute's whole value names (`$name`, not shadowed by a catalog's
  /// own), if it does.
  [[nodiscard]] std::optional<std::string> parameter_of(const xml::Element& e, std::string_view name) const;

  [[nodiscard]] const ParameterScope& scope() const noexcept { return scope_; }
  [[nodiscard]] const std::filesystem::path& dir() const noexcept { return dir_; }
  [[nodiscard]] Catalogs& catalogs() const noexcept { return catalogs_; }
  [[nodiscard]] const RoadAccess* roads() const noexcept { return roads_; }
  /// The storyboard's element names by type (for StoryboardElementStateCondition).
  std::map<ElementType, std::set<std::string>>* elements_ = nullptr;
  int rev_minor = 3;  ///< the FileHeader's revMinor (defaults differ between versions)
  /// The scenario's global scope, and where the numbers read from its parameters are recorded
  /// (Scenario::uses); null while the globals themselves are read.
  const ParameterScope* global_ = nullptr;
  std::vector<ParameterUse>* uses_ = nullptr;

 private:
  const ParameterScope& scope_;
  std::filesystem::path dir_;
  Catalogs& catalogs_;
  const std::set<std::string>& entities_;
  const RoadAccess* roads_;
};

/// Declares the ParameterDeclarations of `parent` (if any) in `scope`.
void declare_parameters(const xml::Element& parent, ParameterScope& scope, const ReadContext& context,
                        const ParameterOverrides& overrides);

/// A catalog entry of the given element name (Vehicle, Maneuver, Trajectory, ...) a
/// CatalogReference names, with a scope holding its declarations as the ParameterAssignments set
/// them. The scope's parent is `context`'s scope.
struct CatalogEntry {
  xml::Element element;
  std::unique_ptr<ParameterScope> scope;
};
[[nodiscard]] CatalogEntry resolve_catalog_reference(const xml::Element& reference, const ReadContext& context);

// The parts of the document (read_positions.cpp, read_actions.cpp, read_conditions.cpp).
[[nodiscard]] Position read_position(const xml::Element& position, const ReadContext& context);
[[nodiscard]] Action read_private_action(const xml::Element& private_action, const std::string& actor,
                                         const ReadContext& context);
[[nodiscard]] Trigger read_trigger(const xml::Element& trigger, const ReadContext& context);
[[nodiscard]] Entity read_entity(const xml::Element& scenario_object, const ReadContext& context);
/// The controller an ObjectController or AssignControllerAction holds (directly or from a catalog)
/// when it is not esmini's default; nullopt for the default (controllers.cpp).
[[nodiscard]] std::optional<ControllerRef> read_controller(const xml::Element& holder, const ReadContext& context);
/// Refuses a controller other than esmini's default on any entity but `scenario.ego`, at the
/// controller's type (controllers.cpp).
void check_controllers(const Scenario& scenario);

}  // namespace emrm::openscenario::detail
