#pragma once

// The inside of an xml::Document, shared by document.cpp and schema.cpp (not a public header).

#include <libxml/tree.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "emrm/xml/document.hpp"

namespace emrm::xml::detail {

/// Initialises libxml2 once (thread-safe); every entry point calls it first.
void ensure_libxml();

struct DocumentData {
  std::string file;
  std::string text;                      // the source, to find columns in
  xmlDocPtr doc = nullptr;               // owned
  std::vector<std::size_t> line_starts;  // byte offset of each line's first character
  std::vector<std::size_t> tag_offsets;  // byte offset of the k-th start tag's '<'; an element's
                                         // _private points at its own (null: fall back on lines)
  DocumentData() = default;
  DocumentData(const DocumentData&) = delete;
  DocumentData& operator=(const DocumentData&) = delete;
  ~DocumentData() { xmlFreeDoc(doc); }

  /// file:line:column of a byte offset in text.
  [[nodiscard]] SourceLocation location(std::size_t offset) const;
  /// The byte offset of an element's start tag, if known.
  [[nodiscard]] bool tag_offset(const xmlNode* node, std::size_t& offset) const;
};

struct Access {
  static const std::shared_ptr<const DocumentData>& data(const Document& document) { return document.data_; }
  static const xmlNode* node(const Element& element) { return static_cast<const xmlNode*>(element.node_); }
  static Element element(const Element& any_of_document, const xmlNode* node) {
    return Element(any_of_document.document_, node);
  }
};

}  // namespace emrm::xml::detail
