#include "emrm/xml/document.hpp"

#include <libxml/parser.h>
#include <libxml/xmlerror.h>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <fstream>
#include <mutex>
#include <sstream>

#include "document_data.hpp"

namespace emrm::xml {
namespace detail {

void ensure_libxml() {
  static std::once_flag once;
  std::call_once(once, [] { xmlInitParser(); });
}

SourceLocation DocumentData::location(std::size_t offset) const {
  const auto after = std::upper_bound(line_starts.begin(), line_starts.end(), offset);
  const auto line = static_cast<std::size_t>(after - line_starts.begin());  // >= 1: line_starts[0] == 0
  return {file, static_cast<int>(line), static_cast<int>(offset - line_starts[line - 1] + 1)};
}

bool DocumentData::tag_offset(const xmlNode* node, std::size_t& offset) const {
  if (node->_private == nullptr) return false;
  offset = *static_cast<const std::size_t*>(node->_private);
  return true;
}

}  // namespace detail

namespace {

using detail::DocumentData;

std::string_view as_view(const xmlChar* text) {
  return text == nullptr ? std::string_view{} : std::string_view(reinterpret_cast<const char*>(text));
}

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
bool ends_name(char c) { return is_blank(c) || c == '>' || c == '/' || c == '='; }

/// The byte offsets of the start tags in `text`, in document order: comments, CDATA sections,
/// processing instructions, declarations and end tags are skipped, and quoted attribute values
/// inside a tag are not searched.
std::vector<std::size_t> scan_start_tags(const std::string& text) {
  std::vector<std::size_t> tags;
  const auto skip_past = [&](std::size_t from, std::string_view end) {
    const std::size_t at = text.find(end, from);
    return at == std::string::npos ? text.size() : at + end.size();
  };
  std::size_t i = 0;
  while ((i = text.find('<', i)) != std::string::npos) {
    const std::string_view rest = std::string_view(text).substr(i);
    if (rest.starts_with("<!--")) {
      i = skip_past(i + 4, "-->");
    } else if (rest.starts_with("<![CDATA[")) {
      i = skip_past(i + 9, "]]>");
    } else if (rest.starts_with("<?")) {
      i = skip_past(i + 2, "?>");
    } else if (rest.starts_with("<!") || rest.starts_with("</")) {
      i = skip_past(i + 2, ">");
    } else {
      tags.push_back(i);
      char quote = 0;
      for (++i; i < text.size(); ++i) {  // to the tag's end, past quoted values
        if (quote != 0) {
          if (text[i] == quote) quote = 0;
        } else if (text[i] == '"' || text[i] == '\'') {
          quote = text[i];
        } else if (text[i] == '>') {
          break;
        }
      }
    }
  }
  return tags;
}

/// Points each element's _private at its start tag's offset, when the elements and the tags found
/// in the text agree in number (they do for any well-formed document without entity references).
void number_elements(DocumentData& data) {
  std::vector<xmlNode*> elements;
  std::vector<xmlNode*> stack{xmlDocGetRootElement(data.doc)};
  while (!stack.empty()) {  // pre-order: document order of start tags
    xmlNode* node = stack.back();
    stack.pop_back();
    if (node == nullptr) continue;
    elements.push_back(node);
    std::vector<xmlNode*> kids;
    for (xmlNode* c = node->children; c != nullptr; c = c->next)
      if (c->type == XML_ELEMENT_NODE) kids.push_back(c);
    stack.insert(stack.end(), kids.rbegin(), kids.rend());
  }
  if (elements.size() != data.tag_offsets.size()) return;  // columns fall back on the line's first match
  for (std::size_t k = 0; k < elements.size(); ++k) elements[k]->_private = &data.tag_offsets[k];
}

const xmlNode* as_node(const void* node) { return static_cast<const xmlNode*>(node); }

std::string qualified_name(const xmlNode* node) {
  std::string name;
  if (node->ns != nullptr && node->ns->prefix != nullptr) name = std::string(as_view(node->ns->prefix)) + ":";
  return name + std::string(as_view(node->name));
}

/// The offset of the element's start tag: from its number, or the first "<name" on its line.
std::optional<std::size_t> start_tag(const DocumentData& data, const xmlNode* node) {
  std::size_t offset = 0;
  if (data.tag_offset(node, offset)) return offset;
  const long line = xmlGetLineNo(node);
  if (line < 1 || static_cast<std::size_t>(line) > data.line_starts.size()) return std::nullopt;
  const std::size_t begin = data.line_starts[static_cast<std::size_t>(line - 1)];
  const std::size_t at = data.text.find("<" + qualified_name(node), begin);
  const std::size_t end = static_cast<std::size_t>(line) < data.line_starts.size()
                              ? data.line_starts[static_cast<std::size_t>(line)]
                              : data.text.size();
  if (at == std::string::npos || at >= end) return std::nullopt;
  return at;
}

/// The offset of `attribute`'s name inside the start tag at `tag` (its qualified or local name).
std::optional<std::size_t> attribute_in_tag(const std::string& text, std::size_t tag, std::string_view attribute) {
  std::size_t i = tag + 1;
  while (i < text.size() && !ends_name(text[i])) ++i;  // the tag's name
  while (i < text.size()) {
    while (i < text.size() && is_blank(text[i])) ++i;
    if (i >= text.size() || text[i] == '>' || text[i] == '/') return std::nullopt;
    const std::size_t name_at = i;
    while (i < text.size() && !ends_name(text[i])) ++i;
    const std::string_view name = std::string_view(text).substr(name_at, i - name_at);
    const std::size_t colon = name.find(':');
    if (name == attribute || (colon != std::string_view::npos && name.substr(colon + 1) == attribute)) return name_at;
    while (i < text.size() && (is_blank(text[i]) || text[i] == '=')) ++i;
    if (i >= text.size()) return std::nullopt;
    const char quote = text[i];
    if (quote != '"' && quote != '\'') return std::nullopt;
    const std::size_t close = text.find(quote, i + 1);
    if (close == std::string::npos) return std::nullopt;
    i = close + 1;
  }
  return std::nullopt;
}

std::vector<std::size_t> line_starts_of(const std::string& text) {
  std::vector<std::size_t> starts{0};
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') starts.push_back(i + 1);
  return starts;
}

std::string trimmed(std::string_view text) {
  while (!text.empty() && is_blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_blank(text.back())) text.remove_suffix(1);
  return std::string(text);
}

/// The first error libxml2 raises while parsing (the later ones follow from it).
struct FirstError {
  bool set = false;
  int line = 0;
  int column = 0;
  std::string message;
};

void keep_first_error(void* user, xmlErrorPtr error) {
  auto* first = static_cast<FirstError*>(static_cast<xmlParserCtxtPtr>(user)->_private);
  if (first->set || error == nullptr || error->level < XML_ERR_ERROR) return;
  *first = {true, error->line, error->int2, trimmed(as_view(reinterpret_cast<const xmlChar*>(error->message)))};
}

}  // namespace

Document Document::parse(const std::string& text, const std::string& file_name) {
  detail::ensure_libxml();
  auto data = std::make_shared<DocumentData>();
  data->file = file_name;
  data->text = text;
  data->line_starts = line_starts_of(text);
  if (text.size() > static_cast<std::size_t>(INT_MAX)) throw InputError({file_name, 0, 0}, "the file is too large");

  xmlParserCtxtPtr context = xmlNewParserCtxt();
  if (context == nullptr) throw std::bad_alloc();
  FirstError first;
  context->_private = &first;
  context->sax->serror = keep_first_error;
  // No network, no DTD loading, no entity substitution (the defaults without NOENT/DTDLOAD);
  // lines past 65535 kept; errors collected here instead of printed.
  const int options = XML_PARSE_NONET | XML_PARSE_BIG_LINES | XML_PARSE_NOERROR | XML_PARSE_NOWARNING;
  data->doc =
      xmlCtxtReadMemory(context, text.data(), static_cast<int>(text.size()), file_name.c_str(), nullptr, options);
  const bool well_formed = data->doc != nullptr && context->wellFormed != 0;
  if (!well_formed && !first.set) {
    if (const xmlError* last = xmlCtxtGetLastError(context); last != nullptr)
      first = {true, last->line, last->int2, trimmed(as_view(reinterpret_cast<const xmlChar*>(last->message)))};
  }
  xmlFreeParserCtxt(context);
  if (!well_formed)
    throw InputError({file_name, first.line, first.column},
                     "malformed XML: " + (first.set ? first.message : std::string("cannot be parsed")));
  if (data->doc->intSubset != nullptr || data->doc->extSubset != nullptr) {
    const std::size_t at = text.find("<!DOCTYPE");
    throw InputError(at == std::string::npos ? SourceLocation{file_name, 0, 0} : data->location(at),
                     "a DOCTYPE is not accepted (OpenDRIVE and OpenSCENARIO files have none)");
  }
  if (xmlDocGetRootElement(data->doc) == nullptr) throw InputError({file_name, 1, 1}, "the XML has no root element");
  data->tag_offsets = scan_start_tags(text);
  number_elements(*data);
  return Document(std::move(data));
}

Document Document::load(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError({file.string(), 0, 0}, "cannot open the file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError({file.string(), 0, 0}, "cannot read the file");
  return parse(text.str(), file.string());
}

Element Document::root() const { return Element(data_, xmlDocGetRootElement(data_->doc)); }
const std::string& Document::file() const { return data_->file; }

std::string_view Element::name() const { return as_view(as_node(node_)->name); }

SourceLocation Element::where() const {
  if (const auto tag = start_tag(*document_, as_node(node_))) return document_->location(*tag);
  return {document_->file, static_cast<int>(xmlGetLineNo(as_node(node_))), 0};
}

SourceLocation Element::where(std::string_view attribute) const {
  if (const auto tag = start_tag(*document_, as_node(node_)))
    if (const auto at = attribute_in_tag(document_->text, *tag, attribute)) return document_->location(*at);
  return where();
}

std::optional<std::string> Element::attribute(std::string_view name) const {
  for (const xmlAttr* a = as_node(node_)->properties; a != nullptr; a = a->next) {
    if (as_view(a->name) != name) continue;
    xmlChar* value = xmlNodeListGetString(as_node(node_)->doc, a->children, 1);
    std::string text(as_view(value));
    xmlFree(value);
    return text;
  }
  return std::nullopt;
}

std::string Element::required(std::string_view name) const {
  if (auto value = attribute(name)) return *value;
  fail("<" + std::string(this->name()) + "> needs the attribute " + std::string(name));
}

std::optional<double> Element::optional_number(std::string_view name) const {
  const auto text = attribute(name);
  if (!text) return std::nullopt;
  std::string_view digits = *text;
  while (!digits.empty() && is_blank(digits.front())) digits.remove_prefix(1);
  while (!digits.empty() && is_blank(digits.back())) digits.remove_suffix(1);
  if (digits.starts_with('+')) digits.remove_prefix(1);  // xs:double allows it, from_chars does not
  double value = 0.0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  const bool whole = !digits.empty() && error == std::errc{} && end == digits.data() + digits.size();
  const std::string said = "<" + std::string(this->name()) + "> attribute " + std::string(name) + "=\"" + *text + "\"";
  if (!whole) fail(name, said + ": expected a number (decimal or exponent form)");
  if (!std::isfinite(value)) fail(name, said + ": expected a number, finite (not NaN or infinity)");
  return value;
}

double Element::number(std::string_view name) const {
  if (auto value = optional_number(name)) return *value;
  fail("<" + std::string(this->name()) + "> needs the attribute " + std::string(name) + ": expected a number");
}

std::vector<Element> Element::children() const {
  std::vector<Element> out;
  for (const xmlNode* c = as_node(node_)->children; c != nullptr; c = c->next)
    if (c->type == XML_ELEMENT_NODE) out.push_back(Element(document_, c));
  return out;
}

std::vector<Element> Element::children(std::string_view name) const {
  std::vector<Element> out;
  for (const xmlNode* c = as_node(node_)->children; c != nullptr; c = c->next)
    if (c->type == XML_ELEMENT_NODE && as_view(c->name) == name) out.push_back(Element(document_, c));
  return out;
}

std::optional<Element> Element::child(std::string_view name) const {
  for (const xmlNode* c = as_node(node_)->children; c != nullptr; c = c->next)
    if (c->type == XML_ELEMENT_NODE && as_view(c->name) == name) return Element(document_, c);
  return std::nullopt;
}

Element Element::required_child(std::string_view name) const {
  if (auto found = child(name)) return *found;
  fail("<" + std::string(this->name()) + "> needs a <" + std::string(name) + "> element");
}

std::optional<Element> Element::parent() const {
  const xmlNode* up = as_node(node_)->parent;
  if (up == nullptr || up->type != XML_ELEMENT_NODE) return std::nullopt;
  return Element(document_, up);
}

std::string Element::text() const {
  xmlChar* content = xmlNodeGetContent(as_node(node_));
  std::string text(as_view(content));
  xmlFree(content);
  return text;
}

void Element::fail(const std::string& message) const { throw InputError(where(), message); }
void Element::fail(std::string_view attribute, const std::string& message) const {
  throw InputError(where(attribute), message);
}

}  // namespace emrm::xml
