#pragma once

// A small indenting XML writer for the exchange formats: elements with attributes, escaped values,
// numbers as people read them (core::readable_number). Internal to src/exchange.

#include <fmt/format.h>

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "emrm/core/text.hpp"

namespace emrm::exchange {

/// A number as XML holds it: at most 15 significant digits, no float noise (4.95, not
/// 4.9500000000000002); within 5e-15 of the double, far below a simulator's millimetre.
inline std::string xml_number(double x) { return core::readable_number(x); }

class XmlWriter {
 public:
  using Attributes = std::vector<std::pair<std::string_view, std::string>>;

  XmlWriter() { out_ = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"; }

  /// A comment line (the text must not contain "--").
  void comment(std::string_view text) {
    indent();
    out_ += "<!-- ";
    out_ += text;
    out_ += " -->\n";
  }
  void open(std::string_view tag, const Attributes& attributes = {}) {
    start(tag, attributes);
    out_ += ">\n";
    open_.emplace_back(tag);
  }
  void leaf(std::string_view tag, const Attributes& attributes = {}) {
    start(tag, attributes);
    out_ += "/>\n";
  }
  void close() {
    const std::string tag = std::move(open_.back());
    open_.pop_back();
    indent();
    out_ += "</" + tag + ">\n";
  }
  [[nodiscard]] std::string str() && { return std::move(out_); }

 private:
  void indent() { out_.append(2 * open_.size(), ' '); }
  void start(std::string_view tag, const Attributes& attributes) {
    indent();
    out_ += '<';
    out_ += tag;
    for (const auto& [name, value] : attributes) {
      out_ += ' ';
      out_ += name;
      out_ += "=\"";
      escape(value);
      out_ += '"';
    }
  }
  void escape(std::string_view text) {
    for (const char c : text) {
      switch (c) {
        case '&':
          out_ += "&amp;";
          break;
        case '<':
          out_ += "&lt;";
          break;
        case '>':
          out_ += "&gt;";
          break;
        case '"':
          out_ += "&quot;";
          break;
        case '\n':
          out_ += "&#10;";
          break;
        default:
          out_ += c;
      }
    }
  }

  std::string out_;
  std::vector<std::string> open_;
};

}  // namespace emrm::exchange
