#pragma once

// libxml2 for the exchange tests: validation against the official XSDs copied into schemas/
// (their ASAM headers intact), and reading numbers back by XPath.

#include <libxml/parser.h>
#include <libxml/tree.h>
#include <libxml/xmlschemas.h>
#include <libxml/xpath.h>

#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace emrm::exchange::testing {

inline std::filesystem::path schema_dir() { return std::filesystem::path(EMRM_SOURCE_DIR) / "schemas"; }
inline std::filesystem::path openscenario_schema() { return schema_dir() / "openscenario" / "OpenSCENARIOv1.2.xsd"; }
inline std::filesystem::path opendrive_schema() {
  return schema_dir() / "opendrive" / "OpenDRIVE_1.6" / "opendrive_16_core.xsd";
}

/// A parsed XSD, kept for the test program's life (parsing OpenSCENARIO's takes a while).
class Schema {
 public:
  explicit Schema(const std::filesystem::path& xsd) {
    xmlSchemaParserCtxtPtr parser = xmlSchemaNewParserCtxt(xsd.string().c_str());
    schema_ = xmlSchemaParse(parser);
    xmlSchemaFreeParserCtxt(parser);
    if (schema_ == nullptr) throw std::runtime_error("cannot parse schema " + xsd.string());
  }
  ~Schema() { xmlSchemaFree(schema_); }
  Schema(const Schema&) = delete;
  Schema& operator=(const Schema&) = delete;

  /// The validation errors of `xml` (one per line), empty when it is valid.
  [[nodiscard]] std::string errors_of(const std::string& xml) const {
    std::string errors;
    xmlDocPtr doc = xmlReadMemory(xml.data(), static_cast<int>(xml.size()), "export.xml", nullptr, XML_PARSE_NONET);
    if (doc == nullptr) return "not well-formed XML";
    xmlSchemaValidCtxtPtr valid = xmlSchemaNewValidCtxt(schema_);
    xmlSchemaSetValidStructuredErrors(
        valid,
        [](void* user, xmlErrorPtr e) {
          auto* out = static_cast<std::string*>(user);
          *out += "line " + std::to_string(e->line) + ": " + (e->message != nullptr ? e->message : "?");
        },
        &errors);
    const int result = xmlSchemaValidateDoc(valid, doc);
    xmlSchemaFreeValidCtxt(valid);
    xmlFreeDoc(doc);
    if (result != 0 && errors.empty()) errors = "invalid (code " + std::to_string(result) + ")";
    return errors;
  }

 private:
  xmlSchemaPtr schema_ = nullptr;
};

inline const Schema& openscenario() {
  static const Schema s(openscenario_schema());
  return s;
}
inline const Schema& opendrive() {
  static const Schema s(opendrive_schema());
  return s;
}

/// A parsed document to query by XPath.
class Document {
 public:
  explicit Document(const std::string& xml)
      : doc_(xmlReadMemory(xml.data(), static_cast<int>(xml.size()), "doc.xml", nullptr, XML_PARSE_NONET)) {
    if (doc_ == nullptr) throw std::runtime_error("not well-formed XML");
  }
  ~Document() { xmlFreeDoc(doc_); }
  Document(const Document&) = delete;
  Document& operator=(const Document&) = delete;

  /// The text values of the nodes (attributes) `xpath` selects, in document order.
  [[nodiscard]] std::vector<std::string> all(const std::string& xpath) const {
    std::vector<std::string> out;
    xmlXPathContextPtr context = xmlXPathNewContext(doc_);
    xmlXPathObjectPtr result = xmlXPathEvalExpression(reinterpret_cast<const xmlChar*>(xpath.c_str()), context);
    if (result != nullptr && result->nodesetval != nullptr) {
      for (int i = 0; i < result->nodesetval->nodeNr; ++i) {
        xmlChar* text = xmlNodeGetContent(result->nodesetval->nodeTab[i]);
        out.emplace_back(reinterpret_cast<const char*>(text));
        xmlFree(text);
      }
    }
    xmlXPathFreeObject(result);
    xmlXPathFreeContext(context);
    return out;
  }
  /// The one number `xpath` selects; throws when it selects none or several.
  [[nodiscard]] double number(const std::string& xpath) const {
    const auto values = all(xpath);
    if (values.size() != 1)
      throw std::runtime_error(xpath + " selects " + std::to_string(values.size()) + " nodes, expected one");
    return std::stod(values.front());
  }

 private:
  xmlDocPtr doc_;
};

}  // namespace emrm::exchange::testing
