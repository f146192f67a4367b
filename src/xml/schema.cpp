// Validation against the ASAM XSDs compiled into the library (schemas/README.md, docs/import.md).
// The schemas are parsed once, from memory: an xs:include is resolved by an external-entity loader
// that serves the embedded files under a URL scheme of their own and hands every other URL to the
// loader it replaced, so the filesystem and the network are never read for a schema.

#include <libxml/parser.h>
#include <libxml/parserInternals.h>
#include <libxml/xmlschemas.h>

#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>

#include "document_data.hpp"
#include "embedded_schemas.hpp"

namespace emrm::xml {
namespace {

constexpr std::string_view kSchemeUrl = "emrm-schema:///";  // + the path under schemas/

xmlExternalEntityLoader previous_loader = nullptr;

xmlParserInputPtr load_embedded(const char* url, const char* id, xmlParserCtxtPtr context) {
  const std::string_view name = url == nullptr ? std::string_view{} : std::string_view(url);
  if (!name.starts_with(kSchemeUrl)) return previous_loader(url, id, context);
  for (const auto& file : detail::embedded_schema_files()) {
    if (file.path != name.substr(kSchemeUrl.size())) continue;
    // The literal is static and NUL-terminated; the input's file name lets includes resolve.
    xmlParserInputPtr input = xmlNewStringInputStream(context, reinterpret_cast<const xmlChar*>(file.text.data()));
    if (input != nullptr) input->filename = reinterpret_cast<char*>(xmlStrdup(reinterpret_cast<const xmlChar*>(url)));
    return input;
  }
  return nullptr;  // an include the embedded files lack: the schema fails to parse (a build error)
}

void install_loader() {
  static std::once_flag once;
  std::call_once(once, [] {
    detail::ensure_libxml();
    previous_loader = xmlGetExternalEntityLoader();
    xmlSetExternalEntityLoader(load_embedded);
  });
}

void ignore_errors(void* /*user*/, xmlErrorPtr /*error*/) {}

/// A compiled schema, kept for the program's life.
class CompiledSchema {
 public:
  explicit CompiledSchema(std::string_view path) {
    install_loader();
    const std::string url = std::string(kSchemeUrl) + std::string(path);
    const std::string_view* text = nullptr;
    for (const auto& file : detail::embedded_schema_files())
      if (file.path == path) text = &file.text;
    if (text == nullptr) throw std::logic_error("no embedded schema " + std::string(path));
    xsd_ = xmlReadMemory(text->data(), static_cast<int>(text->size()), url.c_str(), nullptr,
                         XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING);
    if (xsd_ == nullptr) throw std::logic_error("the embedded schema " + std::string(path) + " is not XML");
    xmlSchemaParserCtxtPtr parser = xmlSchemaNewDocParserCtxt(xsd_);
    xmlSchemaSetParserStructuredErrors(parser, ignore_errors, nullptr);
    schema_ = xmlSchemaParse(parser);
    xmlSchemaFreeParserCtxt(parser);
    if (schema_ == nullptr) throw std::logic_error("the embedded schema " + std::string(path) + " does not compile");
  }
  CompiledSchema(const CompiledSchema&) = delete;
  CompiledSchema& operator=(const CompiledSchema&) = delete;
  ~CompiledSchema() {
    xmlSchemaFree(schema_);
    xmlFreeDoc(xsd_);
  }
  [[nodiscard]] xmlSchemaPtr get() const { return schema_; }

 private:
  xmlDocPtr xsd_ = nullptr;
  xmlSchemaPtr schema_ = nullptr;
};

const CompiledSchema& compiled(std::string_view path) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<CompiledSchema>, std::less<>> schemas;
  const std::lock_guard lock(mutex);
  auto found = schemas.find(path);
  if (found == schemas.end()) found = schemas.emplace(std::string(path), std::make_unique<CompiledSchema>(path)).first;
  return *found->second;
}

/// The file that validates a document, with the standard's name for messages; empty for none.
struct Choice {
  std::string_view path;
  std::string_view standard;
};

/// The header's revMajor/revMinor: <FileHeader> (OpenSCENARIO) or <header> (OpenDRIVE) under the root.
Choice choose(const Document& document, Schema schema) {
  const Element root = document.root();
  const bool drive = schema == Schema::kOpenDrive;
  const std::string_view root_name = drive ? "OpenDRIVE" : "OpenSCENARIO";
  if (root.name() != root_name)
    root.fail("expected <" + std::string(root_name) + "> as the root element, found <" + std::string(root.name()) +
              ">");
  const Element header = root.required_child(drive ? "header" : "FileHeader");
  const double major = header.number("revMajor");
  const double minor = header.number("revMinor");
  if (major != 1.0) header.fail("revMajor", "expected revMajor=\"1\" (version 1.x)");
  if (minor < 0.0 || minor != std::floor(minor)) header.fail("revMinor", "expected a whole revMinor >= 0");
  if (drive) {
    if (minor >= 7.0) return {"opendrive/OpenDRIVE_1.7/opendrive_17_core.xsd", "ASAM OpenDRIVE 1.7"};
    if (minor >= 6.0) return {"opendrive/OpenDRIVE_1.6/opendrive_16_core.xsd", "ASAM OpenDRIVE 1.6"};
    return {};  // 1.4 and 1.5: no schema (docs/import.md)
  }
  if (minor >= 3.0) return {"openscenario/OpenSCENARIOv1.3.xsd", "ASAM OpenSCENARIO 1.3"};
  return {"openscenario/OpenSCENARIOv1.2.xsd", "ASAM OpenSCENARIO 1.2"};
}

struct Violation {
  bool set = false;
  int line = 0;
  const xmlNode* node = nullptr;
  std::string message;
};

void keep_first_violation(void* user, xmlErrorPtr error) {
  auto* first = static_cast<Violation*>(user);
  if (first->set || error == nullptr || error->level < XML_ERR_ERROR) return;
  std::string message = error->message != nullptr ? error->message : "invalid";
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  *first = {true, error->line, static_cast<const xmlNode*>(error->node), message};
}

}  // namespace

bool has_schema(const Document& document, Schema schema) { return !choose(document, schema).path.empty(); }

void validate(const Document& document, Schema schema) {
  const Choice choice = choose(document, schema);
  if (choice.path.empty()) return;
  const CompiledSchema& xsd = compiled(choice.path);
  const auto& data = detail::Access::data(document);

  Violation first;
  xmlSchemaValidCtxtPtr context = xmlSchemaNewValidCtxt(xsd.get());
  if (context == nullptr) throw std::bad_alloc();
  xmlSchemaSetValidStructuredErrors(context, keep_first_violation, &first);
  const int result = xmlSchemaValidateDoc(context, data->doc);
  xmlSchemaFreeValidCtxt(context);
  if (result == 0) return;

  const std::string message = "does not validate against " + std::string(choice.standard) + "'s schema: " +
                              (first.set ? first.message : "invalid (libxml2 code " + std::to_string(result) + ")");
  const xmlNode* node = first.node;
  std::string attribute;
  if (node != nullptr && node->type == XML_ATTRIBUTE_NODE) {
    attribute = reinterpret_cast<const char*>(node->name);
    node = node->parent;
  } else if (const std::size_t at = first.message.find(", attribute '"); at != std::string::npos) {
    // libxml2 reports an attribute's violation on its element and names the attribute in the text.
    const std::size_t begin = at + 13;
    const std::size_t end = first.message.find('\'', begin);
    if (end != std::string::npos) attribute = first.message.substr(begin, end - begin);
  }
  if (node != nullptr && node->type == XML_ELEMENT_NODE && node->doc == data->doc) {
    const Element element = detail::Access::element(document.root(), node);
    // The start tag's own line and column (libxml2's line is where the tag ends, for a tag written
    // over several lines).
    throw InputError(attribute.empty() ? element.where() : element.where(attribute), message);
  }
  throw InputError({data->file, first.line, 0}, message);
}

}  // namespace emrm::xml
