#pragma once

// A read-only XML document with file:line:column on every element and attribute (libxml2 inside),
// for the OpenDRIVE and OpenSCENARIO readers; and validation against the embedded ASAM schemas.
//
// Parsing is hardened for hostile files: no network (XML_PARSE_NONET), no DTD loading, no entity
// substitution, and a document with a DOCTYPE is refused. Every error is an InputError
// "FILE:LINE:COLUMN: error: MESSAGE" (docs/import.md).

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/core/error.hpp"

namespace emrm::xml {

namespace detail {
struct DocumentData;
struct Access;  // the library's own way into a Document's libxml2 tree (src/xml)
}  // namespace detail

/// An element of a Document: a view, cheap to copy, valid while the Document (or a copy of it) lives.
/// Names are local names (a namespace prefix is dropped). Columns count bytes from 1.
class Element {
 public:
  /// The local name ("road" for <road> and for <od:road>).
  [[nodiscard]] std::string_view name() const;
  /// Where the start tag begins (its '<').
  [[nodiscard]] SourceLocation where() const;
  /// Where `attribute`'s name is written in the start tag; the tag's where() when it is absent.
  [[nodiscard]] SourceLocation where(std::string_view attribute) const;

  [[nodiscard]] std::optional<std::string> attribute(std::string_view name) const;
  /// The attribute's text; throws InputError "<Tag> needs the attribute NAME" at the tag when absent.
  [[nodiscard]] std::string required(std::string_view name) const;
  /// The attribute as a finite number: the whole text (surrounding blanks allowed), in decimal or
  /// exponent form. Throws InputError at the attribute naming it, its text and "expected a number"
  /// (absent, not a number, NaN or infinite).
  [[nodiscard]] double number(std::string_view name) const;
  /// As number(), but std::nullopt when the attribute is absent.
  [[nodiscard]] std::optional<double> optional_number(std::string_view name) const;

  /// The element children in document order (all of them, or those of a local name).
  [[nodiscard]] std::vector<Element> children() const;
  [[nodiscard]] std::vector<Element> children(std::string_view name) const;
  /// The first child of that name.
  [[nodiscard]] std::optional<Element> child(std::string_view name) const;
  /// The first child of that name; throws InputError "<Tag> needs a <NAME> element" at the tag.
  [[nodiscard]] Element required_child(std::string_view name) const;
  /// The parent element; std::nullopt for the root.
  [[nodiscard]] std::optional<Element> parent() const;
  /// The concatenated text content (of this element and its descendants).
  [[nodiscard]] std::string text() const;

  /// Throws InputError(where(), message).
  [[noreturn]] void fail(const std::string& message) const;
  /// Throws InputError(where(attribute), message).
  [[noreturn]] void fail(std::string_view attribute, const std::string& message) const;

  /// The same element of the same document.
  friend bool operator==(const Element& a, const Element& b) { return a.node_ == b.node_; }

 private:
  friend class Document;
  friend struct detail::Access;
  Element(std::shared_ptr<const detail::DocumentData> document, const void* node)
      : document_(std::move(document)), node_(node) {}

  std::shared_ptr<const detail::DocumentData> document_;
  const void* node_ = nullptr;  // an xmlNode of document_
};

/// A parsed XML file, immutable. Copies share the parsed tree.
class Document {
 public:
  /// Reads and parses `file`; throws InputError for an unreadable file (no line) or malformed XML
  /// (libxml2's reason at its line and column).
  static Document load(const std::filesystem::path& file);
  /// Parses `text`; `file_name` is the name errors give.
  static Document parse(const std::string& text, const std::string& file_name);

  [[nodiscard]] Element root() const;
  /// The file name errors give.
  [[nodiscard]] const std::string& file() const;

 private:
  explicit Document(std::shared_ptr<const detail::DocumentData> data) : data_(std::move(data)) {}
  friend struct detail::Access;
  std::shared_ptr<const detail::DocumentData> data_;
};

/// The ASAM schemas compiled into the library (schemas/README.md).
enum class Schema { kOpenScenario, kOpenDrive };

/// Validates `document` against the embedded ASAM XSD chosen by its header's revMinor:
/// OpenSCENARIO (<FileHeader revMajor="1">): 1.2's XSD for revMinor 0..2, 1.3's for 3 and above;
/// OpenDRIVE (<header revMajor="1">): 1.7's XSD for revMinor 7 and above, 1.6's for 6; for 4 and 5
/// there is no schema (their files do not validate against 1.6's: docs/import.md) and nothing is
/// checked. Throws InputError at the first violation: libxml2's line, the column of the offending
/// element's tag, and libxml2's reason; and when the root or header is not the schema's.
/// Thread-safe; the schemas are parsed once, from memory (never the filesystem or network).
void validate(const Document& document, Schema schema);

/// Whether validate() checks `document` against an XSD (false for OpenDRIVE 1.4 and 1.5).
[[nodiscard]] bool has_schema(const Document& document, Schema schema);

}  // namespace emrm::xml
