// The messages' encoding (wire.hpp): cereal portable binary archives of the records, the campaign
// and the cells.

#include "wire.hpp"

#include <fmt/format.h>

#include <cereal/archives/portable_binary.hpp>
#include <cereal/types/array.hpp>
#include <cereal/types/optional.hpp>
#include <cereal/types/string.hpp>
#include <cereal/types/vector.hpp>
#include <sstream>
#include <string>

#include "emrm/sim/scene.hpp"

// The records on the wire (found by cereal through argument-dependent lookup, so in the records'
// namespace; this file only).
namespace emrm::campaign {

// The records go over the wire field by field, in their field lists' order (records.hpp), then
// what the lists leave out: an outcome's trajectories, a cell's outcomes.
template <class Archive>
void serialize(Archive& archive, OutcomeRecord& o) {
  OutcomeRecord::visit_fields(o, [&archive](const char*, auto& field, auto...) { archive(field); });
  archive(o.path, o.goal_tree, o.failsafe_tree);
}

template <class Archive>
void serialize(Archive& archive, CellRecord& r) {
  CellRecord::visit_fields(r, [&archive](const char*, auto& field, auto...) { archive(field); });
  archive(r.outcomes);
}

template <class Archive>
void serialize(Archive& archive, CellTask& task) {
  archive(task.grid, task.index, task.cost);
}

// A campaign as the ranks receive it: everything that decides a cell's result (the scene as the
// store keeps it, in YAML); the worker checks that its config hash is rank 0's.
template <class Archive>
void serialize(Archive& archive, GridSpec& grid) {
  archive(grid.name, grid.cells, grid.seeds, grid.keep_trees, grid.levels, grid.adaptive);
}

template <class Archive>
void save(Archive& archive, const Campaign& c) {
  archive(c.file, c.scene_file, sim::to_yaml(c.scene), c.seed, c.strategies, c.grids, c.max_cells, c.text);
}

template <class Archive>
void load(Archive& archive, Campaign& c) {
  std::string scene;
  archive(c.file, c.scene_file, scene, c.seed, c.strategies, c.grids, c.max_cells, c.text);
  c.scene = sim::parse_stored_scene_config(scene, c.file + " (scene from rank 0)");
}

}  // namespace emrm::campaign

namespace emrm::sim {

// A cell's factor values: as many as its scenario has (at most kMaxFactors; more is a damaged message).
template <class Archive>
void save(Archive& archive, const CellInput& cell) {
  archive(std::vector<double>(cell.begin(), cell.end()));
}

template <class Archive>
void load(Archive& archive, CellInput& cell) {
  std::vector<double> values;
  archive(values);
  if (values.size() > kMaxFactors)
    throw cereal::Exception(fmt::format("a cell of {} factor values (at most {})", values.size(), kMaxFactors));
  cell = CellInput(std::span<const double>(values));
}

}  // namespace emrm::sim

namespace emrm::cluster::detail {

template <class Message>
std::string to_archive(const Message& message) {
  std::ostringstream bytes;
  {
    cereal::PortableBinaryOutputArchive archive(bytes);
    archive(message);
  }
  return std::move(bytes).str();
}

template <class Message>
Message from_archive(const std::string& bytes) {
  std::istringstream in(bytes);
  cereal::PortableBinaryInputArchive archive(in);
  Message message;
  archive(message);
  return message;
}

template std::string to_archive(const Job&);
template std::string to_archive(const Chunk&);
template std::string to_archive(const Results&);
template Job from_archive<Job>(const std::string&);
template Chunk from_archive<Chunk>(const std::string&);
template Results from_archive<Results>(const std::string&);

}  // namespace emrm::cluster::detail
