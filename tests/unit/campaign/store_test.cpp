#include "emrm/campaign/store.hpp"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "emrm/campaign/exports.hpp"
#include "scratch.hpp"

namespace emrm::campaign {
namespace store_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = test::scratch_dir("store-test", name);
  fs::create_directories(dir);
  return dir;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

CampaignMeta test_meta(const std::string& hash = "0123456789abcdef") {
  CampaignMeta meta;
  meta.config_hash = hash;
  meta.emrm_version = "test";
  meta.campaign_yaml = "grids: []\n";
  meta.scene_yaml = "name: x\n";
  meta.seed = 18446744073709551557ull;  // above INT64_MAX: must survive the store
  meta.strategies = {"emergency_stop", "emrm"};
  meta.grids = {"first", "second"};
  return meta;
}

CellRecord record(const std::string& grid, std::int64_t index, bool feasible) {
  CellRecord r;
  r.grid = grid;
  r.index = index;
  r.factors = sim::TJunctionCell{30.0 + 0.1 * static_cast<double>(index), 0.31, 0.65, 2.4, 10.0};
  r.seed = 0xfedcba9876543210ull + static_cast<std::uint64_t>(index);
  r.feasible = feasible;
  r.region = feasible ? sim::Region::kY : sim::Region::kInfeasible;
  r.unmitigated_impact_speed_kph = 1.0 / 3.0;
  r.unmitigated_delta_v_kph = 12.5;
  r.unmitigated_p_mais3 = 0.123456789012345;
  r.unmitigated_p_fatal = 1e-17;
  r.unmitigated_loss_level = 6;
  if (!feasible) return r;
  r.evidence = CellEvidence::kWitness;
  r.strengthened = true;
  r.certificate = R"({"method":"test"})";
  r.p_mais3_reduction = 0.123456789012345;
  r.p_fatal_reduction = 1e-17;
  OutcomeRecord stop;
  stop.strategy = "emergency_stop";
  stop.contact = true;
  stop.impact_speed_kph = 20.0 / 3.0;
  stop.delta_v_kph = 5.5;
  stop.p_mais3 = 0.01;
  stop.p_fatal = 0.001;
  stop.loss_level = 4;
  stop.delta_loss = 2;
  stop.min_ttc_s = 0.0;
  stop.fsm_trace = {"S1", "hazard_detected", "S2"};
  stop.evidence = sim::Evidence::kWitness;
  stop.maneuver = R"({"plan":[],"tail":null})";
  OutcomeRecord emrm;
  emrm.strategy = "emrm";
  emrm.avoided = true;
  emrm.road_departure = true;
  emrm.delta_loss = 6;
  emrm.min_ttc_s = std::numeric_limits<double>::infinity();
  emrm.planner_nodes = 123;
  emrm.planner_rollouts = 45;
  emrm.fsm_trace = {"S1", "hazard_detected", "S2", "high_risk", "S3"};
  emrm.loss_evaluation_trace = {"L0", "evaluate", "L1"};
  emrm.chosen_strategy = "dodge";
  emrm.adopted_from = "dodge";
  emrm.evidence = sim::Evidence::kWitness;
  r.outcomes = {stop, emrm};
  return r;
}

// A record's fields as "name=value" by its field list (records.hpp), doubles at full precision:
// equal lists are equal records, whatever fields the list gains.
template <class Record>
std::vector<std::string> fields_of(const Record& record) {
  std::vector<std::string> out;
  Record::visit_fields(record, [&](const char* name, const auto& field, auto...) {
    using T = std::remove_cvref_t<decltype(field)>;
    std::string value;
    if constexpr (core::NamedEnum<T>) {
      value = core::enum_text(field);
    } else if constexpr (std::is_same_v<T, sim::CellInput>) {
      for (const double v : field) value += fmt::format("{} ", v);
    } else if constexpr (std::is_same_v<T, std::vector<std::string>> || std::is_same_v<T, std::vector<std::int64_t>>) {
      value = fmt::format("{}", fmt::join(field, " "));
    } else {
      value = fmt::format("{}", field);
    }
    out.push_back(std::string(name) + "=" + value);
  });
  return out;
}

void expect_equal(const CellRecord& a, const CellRecord& b) {
  EXPECT_EQ(fields_of(a), fields_of(b));
  ASSERT_EQ(a.outcomes.size(), b.outcomes.size());
  for (std::size_t i = 0; i < a.outcomes.size(); ++i) EXPECT_EQ(fields_of(a.outcomes[i]), fields_of(b.outcomes[i]));
}

// Every field of a record, freshly made, set to a value of its own, none its default: `k` counts
// the fields.
template <class Record>
void fill_every_field(Record& record, int k) {
  Record::visit_fields(record, [&](const char*, auto& field, auto...) {
    using T = std::remove_cvref_t<decltype(field)>;
    ++k;
    if constexpr (std::is_same_v<T, bool>) {
      field = true;
    } else if constexpr (std::is_same_v<T, int> || std::is_same_v<T, std::int64_t>) {
      field = k;
    } else if constexpr (std::is_same_v<T, std::uint64_t>) {
      field = 0xfedcba9876543210ull + static_cast<std::uint64_t>(k);
    } else if constexpr (std::is_same_v<T, double>) {
      field = k + 1.0 / 3.0;
    } else if constexpr (std::is_same_v<T, std::string>) {
      field = "text " + std::to_string(k);
    } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
      field = {"a", "b" + std::to_string(k)};
    } else if constexpr (std::is_same_v<T, std::vector<std::int64_t>>) {
      field = {k, k + 1};
    } else if constexpr (std::is_same_v<T, sim::CellInput>) {
      field = sim::TJunctionCell{30.0 + k, 0.5, 0.75, 2.0, 12.0};
    } else {  // the first name that is not the field's default
      for (const auto& [value, name] : core::EnumNames<T>::kNames)
        if (value != field) {
          field = value;
          break;
        }
    }
  });
}

TEST(ResultStore, RecordsRoundTripInGridThenIndexOrder) {
  const auto path = scratch("round_trip") / "results.sqlite";
  const std::vector<CellRecord> written{record("second", 0, true), record("first", 2, false), record("first", 0, true)};
  {
    ResultStore store = ResultStore::open_for_writing(path, test_meta());
    store.insert({written[0], written[1]});
    store.insert({written[2]});
    EXPECT_EQ(store.cell_count(), 3);
  }
  const auto read = read_results(path);
  ASSERT_EQ(read.size(), 3u);
  expect_equal(read[0], written[2]);
  expect_equal(read[1], written[1]);
  expect_equal(read[2], written[0]);
}

TEST(ResultStore, EveryFieldOfTheRecordsFieldListsIsAColumnThatRoundTrips) {
  const auto path = scratch("every_field") / "results.sqlite";
  CellRecord cell;
  fill_every_field(cell, 0);
  cell.grid = "first";
  cell.outcomes.resize(2);
  fill_every_field(cell.outcomes[0], 100);
  fill_every_field(cell.outcomes[1], 200);
  // No field keeps its default, so a field the store dropped would not read back equal.
  const std::vector<std::string> filled = fields_of(cell), defaults = fields_of(CellRecord{});
  ASSERT_EQ(filled.size(), defaults.size());
  for (std::size_t i = 0; i < filled.size(); ++i) EXPECT_NE(filled[i], defaults[i]);
  cell.outcomes[1].min_ttc_s = std::numeric_limits<double>::infinity();  // kept as NULL
  ResultStore::open_for_writing(path, test_meta()).insert({cell});
  const auto read = read_results(path);
  ASSERT_EQ(read.size(), 1u);
  expect_equal(read[0], cell);
  EXPECT_EQ(read[0].outcomes[1].min_ttc_s, std::numeric_limits<double>::infinity());
}

TEST(ResultStore, MetadataRoundTrips) {
  const auto path = scratch("meta") / "results.sqlite";
  const CampaignMeta meta = test_meta();
  (void)ResultStore::open_for_writing(path, meta);
  const CampaignMeta back = read_meta(path);
  EXPECT_EQ(back.config_hash, meta.config_hash);
  EXPECT_EQ(back.emrm_version, meta.emrm_version);
  EXPECT_EQ(back.campaign_yaml, meta.campaign_yaml);
  EXPECT_EQ(back.scene_yaml, meta.scene_yaml);
  EXPECT_EQ(back.seed, meta.seed);
  EXPECT_EQ(back.strategies, meta.strategies);
  EXPECT_EQ(back.grids, meta.grids);
  EXPECT_EQ(back.shard_index, 1);
  EXPECT_EQ(back.shard_count, 1);
}

TEST(ResultStore, ADuplicateCellFailsTheWholeBatch) {
  const auto path = scratch("duplicate") / "results.sqlite";
  ResultStore store = ResultStore::open_for_writing(path, test_meta());
  store.insert({record("first", 0, true)});
  EXPECT_THROW(store.insert({record("first", 1, true), record("first", 0, true)}), Error);
  EXPECT_EQ(store.cell_count(), 1);
}

TEST(ResultStore, ACellWithAnotherNumberOfFactorsFailsTheWholeBatch) {
  const auto path = scratch("factor_count") / "results.sqlite";
  ResultStore store = ResultStore::open_for_writing(path, test_meta());  // the T-junction: five factors
  store.insert({record("first", 0, true)});
  for (const sim::CellInput& factors :
       {sim::CellInput{50.0, 1.0, 1.0}, sim::CellInput{50.0, 1.0, 1.0, 3.0, 10.0, 2.0}}) {
    CellRecord wrong = record("first", 2, true);
    wrong.factors = factors;
    try {
      store.insert({record("first", 1, true), wrong});
      FAIL() << "expected a UsageError";
    } catch (const UsageError& e) {
      EXPECT_THAT(e.what(), HasSubstr(fmt::format("has {} factors, the store's scene 5", factors.size())));
    }
    EXPECT_EQ(store.cell_count(), 1);
  }
}

TEST(ResultStore, RefusesAnotherConfigurationNamingBothHashes) {
  const auto path = scratch("other_hash") / "results.sqlite";
  (void)ResultStore::open_for_writing(path, test_meta("aaaaaaaaaaaaaaaa"));
  try {
    (void)ResultStore::open_for_writing(path, test_meta("bbbbbbbbbbbbbbbb"));
    FAIL() << "expected a UsageError";
  } catch (const UsageError& e) {
    EXPECT_THAT(e.what(), HasSubstr("aaaaaaaaaaaaaaaa"));
    EXPECT_THAT(e.what(), HasSubstr("bbbbbbbbbbbbbbbb"));
  }
  CampaignMeta shard = test_meta("aaaaaaaaaaaaaaaa");
  shard.shard_index = 2;
  shard.shard_count = 2;
  EXPECT_THROW((void)ResultStore::open_for_writing(path, shard), UsageError);
}

TEST(ReadMeta, RefusesWhatIsNotAStore) {
  const auto dir = scratch("not_a_store");
  EXPECT_THROW((void)read_meta(dir / "missing.sqlite"), UsageError);
  std::ofstream(dir / "text.sqlite") << "this is not a database, just some text that is long enough\n";
  EXPECT_THROW((void)read_meta(dir / "text.sqlite"), UsageError);
  { std::ofstream empty(dir / "empty.sqlite"); }
  EXPECT_THROW((void)read_meta(dir / "empty.sqlite"), UsageError);
}

// A store whose creation was cut short holds no table (the schema and metadata are one
// transaction); a rerun creates it afresh instead of refusing it as "not a store".
TEST(ResultStore, AnEmptyStoreFileIsCreatedAfresh) {
  const auto path = scratch("empty_store") / "results.sqlite";
  { std::ofstream empty(path); }
  {
    ResultStore store = ResultStore::open_for_writing(path, test_meta());
    store.insert({record("first", 0, true)});
  }
  EXPECT_EQ(read_meta(path).config_hash, test_meta().config_hash);
  EXPECT_EQ(read_results(path).size(), 1u);
  // Text is not an empty store: still refused.
  const auto text = scratch("text_store") / "results.sqlite";
  std::ofstream(text) << "this is not a database, just some text that is long enough\n";
  EXPECT_THROW((void)ResultStore::open_for_writing(text, test_meta()), UsageError);
}

// The names in `dir` that are temporaries of an atomic write (NAME.tmp.PID.N).
std::vector<std::string> temporaries_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().filename().string().find(".tmp") != std::string::npos)
      names.push_back(entry.path().filename().string());
  return names;
}

// The exports stream the whole store: a row that fails half-way (a certificate that is not JSON)
// leaves the previous exports whole and no temporary.
TEST(WriteExports, AFailureHalfWayLeavesThePreviousExportsAndNoTemporary) {
  const auto dir = scratch("exports_fail");
  {
    ResultStore store = ResultStore::open_for_writing(dir / "results.sqlite", test_meta());
    store.insert({record("first", 0, true)});
  }
  write_exports(dir / "results.sqlite", dir);
  const std::string regions = read_text(dir / "regions.csv");
  const std::string cells = read_text(dir / "cells.csv");
  const std::string json = read_text(dir / "cells.json");
  {
    ResultStore store = ResultStore::open_for_writing(dir / "results.sqlite", test_meta());
    CellRecord corrupt = record("second", 0, true);
    corrupt.certificate = "{not json";
    store.insert({record("first", 1, true), corrupt});
  }
  EXPECT_ANY_THROW(write_exports(dir / "results.sqlite", dir));
  EXPECT_EQ(read_text(dir / "regions.csv"), regions);
  EXPECT_EQ(read_text(dir / "cells.csv"), cells);
  EXPECT_EQ(read_text(dir / "cells.json"), json);
  EXPECT_EQ(temporaries_in(dir), std::vector<std::string>{});
}

// cells.json cannot be written (a folder of that name): none of the three exports is.
TEST(WriteExports, AllThreeOrNone) {
  const auto dir = scratch("exports_none");
  {
    ResultStore store = ResultStore::open_for_writing(dir / "results.sqlite", test_meta());
    store.insert({record("first", 0, true)});
  }
  fs::create_directories(dir / "cells.json" / "inside");
  EXPECT_THROW(write_exports(dir / "results.sqlite", dir), Error);
  EXPECT_FALSE(fs::exists(dir / "regions.csv"));
  EXPECT_FALSE(fs::exists(dir / "cells.csv"));
  EXPECT_EQ(temporaries_in(dir), std::vector<std::string>{});
}

TEST(WriteExports, WritesSortedRowsWithTheDocumentedColumns) {
  const auto dir = scratch("exports");
  {
    ResultStore store = ResultStore::open_for_writing(dir / "results.sqlite", test_meta());
    store.insert({record("second", 0, true), record("first", 1, false), record("first", 0, true)});
  }
  write_exports(dir / "results.sqlite", dir);
  EXPECT_EQ(read_text(dir / "regions.csv"),
            "grid,speed_kph,ttc_s,mu,passage_m,truck_speed_kph,feasible,region,evidence,mitigation_evidence,"
            "p_mais3_reduction,p_fatal_reduction,method\n"
            "first,30,0.31,0.65,2.4,10,1,Y,witness,,0.123457,1e-17,simulated\n"
            "first,30.1,0.31,0.65,2.4,10,0,infeasible,,,,,\n"
            "second,30,0.31,0.65,2.4,10,1,Y,witness,,0.123457,1e-17,simulated\n");
  const std::string cells = read_text(dir / "cells.csv");
  EXPECT_THAT(cells, HasSubstr("grid,speed_kph,ttc_s,mu,passage_m,truck_speed_kph,strategy,avoided,"
                               "impact_speed_kph,delta_v_kph,loss_level,delta_loss,min_ttc_s,road_departure,"
                               "departure_speed_kph,evidence\n"
                               "first,30,0.31,0.65,2.4,10,emergency_stop,0,6.66667,5.5,4,2,0,0,0,witness\n"
                               "first,30,0.31,0.65,2.4,10,emrm,1,0,0,0,6,inf,1,0,witness\n"
                               "second,30,0.31,0.65,2.4,10,emergency_stop,0,"));
  EXPECT_TRUE(fs::exists(dir / "cells.json"));
}

TEST(Merge, JoinsStoresOfOneConfigurationAndRefusesOthers) {
  const auto a = scratch("merge_a");
  const auto b = scratch("merge_b");
  const auto c = scratch("merge_c");
  const auto out = scratch("merge_out");
  CampaignMeta shard1 = test_meta();
  shard1.shard_count = 2;
  CampaignMeta shard2 = shard1;
  shard2.shard_index = 2;
  ResultStore::open_for_writing(a / "results.sqlite", shard1).insert({record("first", 0, true)});
  ResultStore::open_for_writing(b / "results.sqlite", shard2).insert({record("first", 1, true)});
  (void)ResultStore::open_for_writing(c / "results.sqlite", test_meta("ffffffffffffffff"));
  merge({a, b}, out);
  const auto merged = read_results(out / "results.sqlite");
  ASSERT_EQ(merged.size(), 2u);
  expect_equal(merged[0], record("first", 0, true));
  expect_equal(merged[1], record("first", 1, true));
  EXPECT_EQ(read_meta(out / "results.sqlite").shard_count, 1);
  EXPECT_TRUE(fs::exists(out / "cells.csv"));
  EXPECT_THROW(merge({a, c}, scratch("merge_bad")), UsageError);
}

}  // namespace store_test
}  // namespace emrm::campaign
