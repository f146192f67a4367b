#pragma once

// The shipped T-junction safety case as text, and edits of it for tests of bad input.

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace emrm::safety::testing {

inline std::string example_text() {
  std::ifstream in(std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/safety.yaml");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// `text` with the first `from` replaced by `to`; throws if `from` is absent, so a test cannot
/// silently run on an unedited file.
inline std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  if (pos == std::string::npos) throw std::logic_error("test edit did not apply: " + from);
  return text.replace(pos, from.size(), to);
}

/// 1-based line of the first occurrence of `needle`.
inline int line_of(const std::string& text, const std::string& needle) {
  const auto pos = text.find(needle);
  if (pos == std::string::npos) throw std::logic_error("not in text: " + needle);
  int line = 1;
  for (std::size_t i = 0; i < pos; ++i) line += text[i] == '\n';
  return line;
}

/// 1-based column of the first occurrence of `needle`.
inline int column_of(const std::string& text, const std::string& needle) {
  const auto pos = text.find(needle);
  if (pos == std::string::npos) throw std::logic_error("not in text: " + needle);
  const auto line_start = text.rfind('\n', pos);
  return static_cast<int>(pos - (line_start == std::string::npos ? 0 : line_start + 1)) + 1;
}

}  // namespace emrm::safety::testing
