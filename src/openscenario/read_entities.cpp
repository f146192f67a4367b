// Entities as the document writes them (read_context.hpp): a Vehicle, Pedestrian or MiscObject,
// directly or from a catalog, and its controller (controllers.cpp).

#include <fmt/format.h>

#include <optional>

#include "read_context.hpp"

namespace emrm::openscenario::detail {
namespace {

constexpr double kMaxSize_m = 1000.0;

BoundingBox read_box(const xml::Element& object, const ReadContext& c) {
  const xml::Element box = object.required_child("BoundingBox");
  const xml::Element center = box.required_child("Center");
  const xml::Element dimensions = box.required_child("Dimensions");
  return {c.number(center, "x", "m", -kMaxSize_m, kMaxSize_m),  c.number(center, "y", "m", -kMaxSize_m, kMaxSize_m),
          c.number(center, "z", "m", -kMaxSize_m, kMaxSize_m),  c.number(dimensions, "width", "m", 0.0, kMaxSize_m),
          c.number(dimensions, "length", "m", 0.0, kMaxSize_m), c.number(dimensions, "height", "m", 0.0, kMaxSize_m)};
}

void read_object(Entity& entity, const xml::Element& object, const ReadContext& c) {
  const std::string_view kind = object.name();
  entity.box = read_box(object, c);
  entity.mass_kg = c.optional_number(object, "mass", "kg", 0.0, 1e6);
  if (entity.mass_kg && *entity.mass_kg <= 0.0) entity.mass_kg.reset();  // esmini's samples write 0 for none
  if (kind == "Vehicle") {
    entity.kind = EntityKind::kVehicle;
    entity.category = c.text(object, "vehicleCategory");
    const xml::Element p = object.required_child("Performance");
    entity.performance = {c.number(p, "maxSpeed", "m/s", 0.0, 1e4), c.number(p, "maxAcceleration", "m/s2", 0.0, 1e4),
                          c.number(p, "maxDeceleration", "m/s2", 0.0, 1e4)};
  } else if (kind == "Pedestrian") {
    entity.kind = EntityKind::kPedestrian;
    entity.category = c.optional_text(object, "pedestrianCategory").value_or("pedestrian");
  } else if (kind == "MiscObject") {
    entity.kind = EntityKind::kMiscObject;
    entity.category = c.text(object, "miscObjectCategory");
    entity.performance = {0.0, 0.0, 0.0};  // esmini: an object does not drive (its speed is held at 0)
  } else {
    object.fail(
        fmt::format("a catalog entry of kind {} is not an entity (expected Vehicle, Pedestrian or MiscObject)", kind));
  }
}

}  // namespace

Entity read_entity(const xml::Element& scenario_object, const ReadContext& c) {
  Entity entity;
  entity.name = c.text(scenario_object, "name");
  entity.where = scenario_object.where();
  const xml::Element object = c.chosen(scenario_object, "EntityObject");
  if (object.name() == "CatalogReference") {
    const CatalogEntry entry = resolve_catalog_reference(object, c);
    read_object(entity, entry.element, c.with(*entry.scope));
  } else {
    read_object(entity, object, c);
  }
  for (const xml::Element& controller : scenario_object.children("ObjectController"))
    if (auto other = read_controller(controller, c)) entity.controller = std::move(other);
  return entity;
}

}  // namespace emrm::openscenario::detail
