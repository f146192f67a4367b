// xml::Document: every element and attribute knows its file:line:column, malformed XML and bad
// numbers are InputErrors that say where and what was expected.

#include "emrm/xml/document.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>

namespace emrm::xml {
namespace {

using ::testing::HasSubstr;

InputError error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError";
  return InputError({}, "");
}

// Column of the first occurrence of `needle` on its line, counted as the text says (1-based bytes).
SourceLocation located(const std::string& text, const std::string& needle, std::size_t from = 0) {
  const std::size_t at = text.find(needle, from);
  const std::size_t line_start = text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at) + 1;
  const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
  return {"t.xml", static_cast<int>(line), static_cast<int>(at - line_start + 1)};
}

const std::string kText =
    "<?xml version=\"1.0\"?>\n"
    "<!-- <road id=\"decoy\"> in a comment -->\n"
    "<root a=\"1\">\n"
    "  <road id=\"r1\" length=\" 2.5e1 \"/><road id='r2' length=\"x\"\n"
    "     note=\"a > b\" count=\"NaN\" big=\"inf\"/>\n"
    "  <other><![CDATA[<road id=\"no\">]]>text</other>\n"
    "</root>\n";

TEST(XmlDocument, ElementsKnowTheirStartTagsLineAndColumn) {
  const Document doc = Document::parse(kText, "t.xml");
  const Element root = doc.root();
  EXPECT_EQ(root.name(), "root");
  const auto roads = root.children("road");
  ASSERT_EQ(roads.size(), 2U);
  const SourceLocation first = roads[0].where();
  const SourceLocation expected_first = located(kText, "<road id=\"r1\"");
  EXPECT_EQ(first.line, expected_first.line);
  EXPECT_EQ(first.column, expected_first.column);
  // The second <road> on the same line: its own column, not the first's.
  const SourceLocation second = roads[1].where();
  const SourceLocation expected_second = located(kText, "<road id='r2'");
  EXPECT_EQ(second.line, expected_second.line);
  EXPECT_EQ(second.column, expected_second.column);
  // An attribute on the next line of a tag, after a value holding '>'.
  const SourceLocation count = roads[1].where("count");
  const SourceLocation expected_count = located(kText, "count=");
  EXPECT_EQ(count.line, expected_count.line);
  EXPECT_EQ(count.column, expected_count.column);
  EXPECT_EQ(roads[1].where("absent").column, second.column);  // falls back on the tag
  EXPECT_EQ(root.child("other")->text(), "<road id=\"no\">text");
  EXPECT_EQ(*roads[0].parent(), root);
  EXPECT_FALSE(root.parent().has_value());
  EXPECT_EQ(root.children().size(), 3U);
}

TEST(XmlDocument, NumbersAreWholeFiniteAttributes) {
  const Document doc = Document::parse(kText, "t.xml");
  const auto roads = doc.root().children("road");
  EXPECT_DOUBLE_EQ(roads[0].number("length"), 25.0);
  EXPECT_FALSE(roads[0].optional_number("absent").has_value());
  EXPECT_EQ(roads[0].required("id"), "r1");

  for (const std::string attribute : {"length", "count", "big"}) {
    const InputError e = error_of([&] { (void)roads[1].number(attribute); });
    EXPECT_THAT(e.message(), HasSubstr(attribute));
    EXPECT_THAT(e.message(), HasSubstr("expected a number"));
    const SourceLocation expected = located(kText, attribute + "=", kText.find("r2"));
    EXPECT_EQ(e.where().line, expected.line) << attribute;
    EXPECT_EQ(e.where().column, expected.column) << attribute;
  }
  const InputError missing = error_of([&] { (void)roads[0].required("width"); });
  EXPECT_EQ(missing.message(), "<road> needs the attribute width");
  EXPECT_EQ(missing.where().column, located(kText, "<road id=\"r1\"").column);
  EXPECT_THAT(error_of([&] { (void)roads[0].number("width"); }).message(), HasSubstr("width"));
  EXPECT_THAT(error_of([&] { (void)doc.root().required_child("lane"); }).message(), HasSubstr("<lane>"));
}

TEST(XmlDocument, NumbersInEveryDecimalForm) {
  const Document doc = Document::parse(R"(<n a="+1.5" b="-2E-3" c=".5" d="7" e="1e400" f="0x10" g=""/>)", "n.xml");
  const Element n = doc.root();
  EXPECT_DOUBLE_EQ(n.number("a"), 1.5);
  EXPECT_DOUBLE_EQ(n.number("b"), -2e-3);
  EXPECT_DOUBLE_EQ(n.number("c"), 0.5);
  EXPECT_DOUBLE_EQ(n.number("d"), 7.0);
  for (const char* bad : {"e", "f", "g"}) EXPECT_THROW((void)n.number(bad), InputError) << bad;
}

TEST(XmlDocument, MalformedXmlSaysLineAndColumn) {
  // An unclosed tag's mismatch is found at the end tag on line 3.
  const InputError e = error_of([] { (void)Document::parse("<a>\n  <b>\n  </c>\n</a>\n", "bad.xml"); });
  EXPECT_EQ(e.where().file, "bad.xml");
  EXPECT_EQ(e.where().line, 3);
  EXPECT_GT(e.where().column, 0);
  EXPECT_THAT(e.message(), HasSubstr("malformed XML"));
  // An attribute without quotes: line 2, at or just after the value.
  const InputError quote = error_of([] { (void)Document::parse("<a>\n  <b x=1/>\n</a>", "q.xml"); });
  EXPECT_EQ(quote.where().line, 2);
  EXPECT_GE(quote.where().column, 8);
  EXPECT_THROW((void)Document::parse("", "empty.xml"), InputError);
  EXPECT_THROW((void)Document::parse("<a>", "open.xml"), InputError);
}

TEST(XmlDocument, RefusesDoctypeAndEntities) {
  const std::string bomb =
      "<?xml version=\"1.0\"?>\n<!DOCTYPE a [<!ENTITY x \"xxxxxxxx\"><!ENTITY y \"&x;&x;&x;&x;\">]>\n<a>&y;</a>";
  const InputError e = error_of([&] { (void)Document::parse(bomb, "bomb.xml"); });
  EXPECT_EQ(e.where().line, 2);
  EXPECT_EQ(e.where().column, 1);
  EXPECT_THAT(e.message(), HasSubstr("DOCTYPE"));
  const std::string external = "<!DOCTYPE a SYSTEM \"http://example.invalid/a.dtd\">\n<a/>";
  EXPECT_THROW((void)Document::parse(external, "ext.xml"), InputError);
}

TEST(XmlDocument, WindowsLineEndsAndNamespacePrefixes) {
  const std::string text = "<?xml version=\"1.0\"?>\r\n<a xmlns:p=\"urn:x\">\r\n  <p:b p:v=\"x\" w=\"1\"/>\r\n</a>\r\n";
  const Element b = Document::parse(text, "crlf.xml").root().children().front();
  EXPECT_EQ(b.name(), "b");
  EXPECT_EQ(b.where().line, 3);
  EXPECT_EQ(b.where().column, 3);
  EXPECT_EQ(b.where("v").column, 8);  // p:v, asked for by its local name
  EXPECT_EQ(b.where("w").column, 16);
  EXPECT_EQ(b.attribute("v"), "x");
}

TEST(XmlDocument, LoadNamesAnUnreadableFile) {
  const InputError e = error_of([] { (void)Document::load("/nonexistent/emrm/road.xodr"); });
  EXPECT_EQ(e.where().file, "/nonexistent/emrm/road.xodr");
  EXPECT_THAT(e.message(), HasSubstr("cannot open"));
}

}  // namespace
}  // namespace emrm::xml
