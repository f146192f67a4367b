// xml::validate against the embedded ASAM schemas: a valid file passes, an invalid one fails at
// the offending element's line and column with libxml2's reason.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

#include "emrm/xml/document.hpp"

namespace emrm::xml {
namespace {

using ::testing::HasSubstr;

std::string scenario(int rev_minor, const std::string& entities) {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<OpenSCENARIO>\n"
         "  <FileHeader revMajor=\"1\" revMinor=\"" +
         std::to_string(rev_minor) +
         "\" date=\"2024-01-01T00:00:00\" description=\"t\" author=\"emrm\"/>\n"
         "  <ParameterDeclarations/>\n"
         "  <CatalogLocations/>\n"
         "  <RoadNetwork/>\n"
         "  " +
         entities +
         "\n"
         "  <Storyboard>\n"
         "    <Init>\n"
         "      <Actions/>\n"
         "    </Init>\n"
         "    <StopTrigger/>\n"
         "  </Storyboard>\n"
         "</OpenSCENARIO>\n";
}

std::string road_network(int rev_minor, const std::string& lane_type) {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<OpenDRIVE>\n"
         "  <header revMajor=\"1\" revMinor=\"" +
         std::to_string(rev_minor) +
         "\" name=\"t\" version=\"1\"/>\n"
         "  <road id=\"1\" length=\"100\" junction=\"-1\">\n"
         "    <link/>\n"
         "    <planView>\n"
         "      <geometry s=\"0\" x=\"0\" y=\"0\" hdg=\"0\" length=\"100\"><line/></geometry>\n"
         "    </planView>\n"
         "    <lanes>\n"
         "      <laneSection s=\"0\">\n"
         "        <center><lane id=\"0\" type=\"none\" level=\"false\"/></center>\n"
         "        <right>\n"
         "          <lane id=\"-1\" type=\"" +
         lane_type +
         "\" level=\"false\"><width sOffset=\"0\" a=\"3.5\" b=\"0\" c=\"0\" d=\"0\"/></lane>\n"
         "        </right>\n"
         "      </laneSection>\n"
         "    </lanes>\n"
         "  </road>\n"
         "</OpenDRIVE>\n";
}

InputError error_of(const Document& doc, Schema schema) {
  try {
    validate(doc, schema);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "valid";
  return InputError({}, "");
}

TEST(XmlSchema, OpenScenarioValidAndInvalid) {
  for (const int minor : {0, 1, 2, 3}) {
    EXPECT_NO_THROW(validate(Document::parse(scenario(minor, "<Entities/>"), "ok.xosc"), Schema::kOpenScenario))
        << minor;
    const Document bad = Document::parse(scenario(minor, "<Entities><Nonsense/></Entities>"), "bad.xosc");
    const InputError e = error_of(bad, Schema::kOpenScenario);
    EXPECT_EQ(e.where().file, "bad.xosc");
    EXPECT_EQ(e.where().line, 7);     // <Nonsense/>
    EXPECT_EQ(e.where().column, 13);  // "  <Entities><" -> the '<' of <Nonsense
    EXPECT_THAT(e.message(), HasSubstr("Nonsense"));
    EXPECT_THAT(e.message(), HasSubstr(minor == 3 ? "OpenSCENARIO 1.3" : "OpenSCENARIO 1.2"));
  }
}

TEST(XmlSchema, OpenDriveValidAndInvalid) {
  for (const int minor : {6, 7}) {
    EXPECT_NO_THROW(validate(Document::parse(road_network(minor, "driving"), "ok.xodr"), Schema::kOpenDrive));
    const Document bad = Document::parse(road_network(minor, "motorway"), "bad.xodr");
    const InputError e = error_of(bad, Schema::kOpenDrive);
    EXPECT_EQ(e.where().line, 13);
    EXPECT_EQ(e.where().column, 25);  // the attribute type of <lane id="-1" ...>
    EXPECT_THAT(e.message(), HasSubstr("motorway"));
    EXPECT_TRUE(has_schema(bad, Schema::kOpenDrive));
  }
  // 1.4 and 1.5 have no schema: nothing is checked.
  const Document old = Document::parse(road_network(4, "motorway"), "old.xodr");
  EXPECT_FALSE(has_schema(old, Schema::kOpenDrive));
  EXPECT_NO_THROW(validate(old, Schema::kOpenDrive));
}

TEST(XmlSchema, ValidatesFromManyThreadsAtOnce) {
  // The schemas are compiled on first use, whichever thread comes first; validation shares them.
  std::vector<std::thread> threads;
  std::vector<int> failures(4, 0);
  for (std::size_t i = 0; i < failures.size(); ++i) {
    threads.emplace_back([i, &failures] {
      for (int round = 0; round < 3; ++round) {
        try {
          validate(Document::parse(scenario(static_cast<int>(i % 4), "<Entities/>"), "t.xosc"), Schema::kOpenScenario);
          validate(Document::parse(road_network(6 + static_cast<int>(i % 2), "driving"), "t.xodr"), Schema::kOpenDrive);
        } catch (const std::exception&) {
          ++failures[i];
        }
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(failures, std::vector<int>(4, 0));
}

TEST(XmlSchema, TheRootMustBeTheSchemas) {
  const Document drive = Document::parse(road_network(7, "driving"), "x.xodr");
  EXPECT_THAT(error_of(drive, Schema::kOpenScenario).message(), HasSubstr("<OpenSCENARIO>"));
  const Document two = Document::parse("<OpenDRIVE>\n<header revMajor=\"2\" revMinor=\"0\"/></OpenDRIVE>", "two.xodr");
  const InputError e = error_of(two, Schema::kOpenDrive);
  EXPECT_EQ(e.where().line, 2);
  EXPECT_EQ(e.where().column, 9);
}

}  // namespace
}  // namespace emrm::xml
