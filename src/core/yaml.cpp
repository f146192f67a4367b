#include "emrm/core/yaml.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "emrm/core/json_archive.hpp"
#include "emrm/core/text.hpp"

namespace emrm::core {
namespace {

SourceLocation location_of(const std::string& file, const YAML::Mark& mark) {
  if (mark.is_null()) return {file, 0, 0};
  return {file, mark.line + 1, mark.column + 1};
}

YAML::Node parse_text(const std::string& text, const std::string& file) {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(location_of(file, e.mark), "malformed YAML: " + e.msg);
  }
}

// YAML spells these .nan, .inf, -.inf (any case); from_chars does not know them.
bool is_yaml_non_finite(const std::string& text) {
  std::string t;
  for (char c : text) t += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return t == ".nan" || t == ".inf" || t == "+.inf" || t == "-.inf";
}

std::string join_keys(const std::vector<std::string>& keys) {
  std::string out;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (i > 0) out += ", ";
    out += keys[i];
  }
  return out;
}

}  // namespace

YamlNode::YamlNode(const YAML::Node& node, std::shared_ptr<const std::string> file)
    : node_(node), file_(std::move(file)) {}

YamlNode YamlNode::load_file(const std::filesystem::path& path) { return parse(read_input_file(path), path.string()); }

YamlNode YamlNode::parse(const std::string& text, std::string file_name) {
  YAML::Node root = parse_text(text, file_name);
  auto file = std::make_shared<const std::string>(std::move(file_name));
  if (!root.IsDefined() || root.IsNull()) throw InputError({*file, 1, 1}, "the file is empty; expected a YAML mapping");
  return YamlNode(root, std::move(file));
}

YamlNode load_json_file(const std::filesystem::path& path) {
  try {
    return YamlNode::load_file(path);
  } catch (const InputError& e) {
    constexpr std::string_view kMalformed = "malformed YAML: ";
    if (e.message().starts_with(kMalformed))
      throw InputError(e.where(), "not valid JSON: " + e.message().substr(kMalformed.size()));
    if (e.message().starts_with("the file is empty")) throw InputError(e.where(), "the file is empty; expected JSON");
    throw;
  }
}

SourceLocation YamlNode::location() const { return location_of(*file_, node_.Mark()); }

void YamlNode::fail(const std::string& message) const { throw InputError(location(), message); }

std::string YamlNode::describe() const {
  if (is_null()) return "nothing";
  if (node_.IsMap()) return "a mapping";
  if (node_.IsSequence()) return "a list";
  return fmt::format("'{}'", node_.Scalar());
}

std::optional<YamlNode> YamlNode::find(std::string_view key) const {
  if (!node_.IsMap()) fail(fmt::format("expected a mapping with field '{}', got {}", key, describe()));
  for (const auto& entry : node_) {
    if (entry.first.IsScalar() && entry.first.Scalar() == key) return YamlNode(entry.second, file_);
  }
  return std::nullopt;
}

YamlNode YamlNode::at(std::string_view key) const {
  auto child = find(key);
  if (!child || child->is_null()) fail(fmt::format("missing required field '{}'", key));
  return *child;
}

std::vector<YamlNode> YamlNode::elements() const {
  if (!node_.IsSequence()) fail("expected a list, got " + describe());
  std::vector<YamlNode> out;
  out.reserve(node_.size());
  for (const auto& element : node_) out.emplace_back(element, file_);
  return out;
}

std::vector<std::pair<YamlNode, YamlNode>> YamlNode::entries() const {
  if (!node_.IsMap()) fail("expected a mapping, got " + describe());
  std::vector<std::pair<YamlNode, YamlNode>> out;
  std::set<std::string> seen;
  for (const auto& entry : node_) {
    YamlNode key(entry.first, file_);
    if (!entry.first.IsScalar()) key.fail("expected a plain key, got " + key.describe());
    if (!seen.insert(entry.first.Scalar()).second) key.fail(fmt::format("duplicate key '{}'", entry.first.Scalar()));
    out.emplace_back(std::move(key), YamlNode(entry.second, file_));
  }
  return out;
}

std::string YamlNode::as_string() const {
  if (!node_.IsScalar()) fail("expected a text value, got " + describe());
  return node_.Scalar();
}

double YamlNode::as_double() const {
  if (!node_.IsScalar()) fail("expected a number, got " + describe());
  const std::string& text = node_.Scalar();
  if (is_yaml_non_finite(text)) fail(fmt::format("expected a finite number, got '{}'", text));
  double value = 0.0;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  if (first != last && *first == '+') ++first;
  auto [ptr, ec] = std::from_chars(first, last, value);
  if (ec != std::errc() || ptr != last || first == last) fail(fmt::format("expected a number, got '{}'", text));
  if (!std::isfinite(value)) fail(fmt::format("expected a finite number, got '{}'", text));
  return value;
}

long long YamlNode::as_int() const {
  if (!node_.IsScalar()) fail("expected an integer, got " + describe());
  const std::string& text = node_.Scalar();
  long long value = 0;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  if (first != last && *first == '+') ++first;
  auto [ptr, ec] = std::from_chars(first, last, value);
  if (ec != std::errc() || ptr != last || first == last) fail(fmt::format("expected an integer, got '{}'", text));
  return value;
}

bool YamlNode::as_bool() const {
  if (node_.IsScalar()) {
    const std::string& text = node_.Scalar();
    if (text == "true" || text == "True" || text == "yes") return true;
    if (text == "false" || text == "False" || text == "no") return false;
  }
  fail("expected true or false, got " + describe());
}

YamlReader::YamlReader(YamlNode map) : node_(std::move(map)) {
  if (!node_.is_map()) node_.fail("expected a mapping, got " + node_.describe());
}

void YamlReader::moved(std::string_view key, std::string_view now_at) const {
  if (auto child = node_.find(key))
    child->fail(fmt::format("'{}' has moved: write it as {} (docs/scene-yaml.md)", key, now_at));
}

void YamlReader::missing(std::string_view key) const {
  // Short names are too near each other (x, y) for a guess; a key a field already claimed is no slip.
  constexpr std::size_t kShortest = 4;
  const std::vector<std::string> wanted{std::string(key)};
  for (const auto& [written, value] : node_.entries()) {
    const std::string name = written.as_string();
    if (key.size() < kShortest || std::find(known_.begin(), known_.end(), name) != known_.end()) continue;
    if (const std::string hint = did_you_mean(name, wanted); !hint.empty())
      written.fail(fmt::format("unknown field '{}'{}; missing required field '{}'", name, hint, key));
  }
  node_.fail(fmt::format("missing required field '{}'", key));
}

void YamlReader::finish() const {
  for (const auto& [key, value] : node_.entries()) {
    const std::string name = key.as_string();
    bool known = false;
    for (const auto& k : known_) known = known || k == name;
    if (!known)
      key.fail(fmt::format("unknown field '{}'{}; expected one of: {}", name, did_you_mean(name, known_),
                           join_keys(known_)));
  }
}

YamlNode node_at(const YamlNode& root, const FieldPath& path) {
  YamlNode node = root;
  for (const FieldPath::Step& step : path.steps) {
    std::optional<YamlNode> child;
    if (const auto* key = std::get_if<std::string>(&step)) {
      if (node.is_map()) child = node.find(*key);
    } else if (const std::size_t index = std::get<std::size_t>(step); node.is_sequence() && index < node.raw().size()) {
      child = node.elements()[index];
    }
    if (!child || child->is_null()) break;
    node = *child;
  }
  return node;
}

void fail_at(const YamlNode& root, const ConfigError& error, bool with_path) {
  const std::string path = error.path().str();
  node_at(root, error.path()).fail(with_path && !path.empty() ? path + ": " + error.detail() : error.detail());
}

YAML::Node yaml_number(double v) {
  if (!std::isfinite(v)) return YAML::Node(v);
  std::array<char, 32> text{};
  char* end = std::to_chars(text.data(), text.data() + text.size(), v).ptr;
  return YAML::Node(std::string(text.data(), static_cast<std::size_t>(end - text.data())));
}

std::string to_yaml_text(const YAML::Node& node) {
  YAML::Emitter out;
  out << node;
  return std::string(out.c_str()) + "\n";
}

namespace {
void make_numbers_readable(YAML::Node node) {
  if (node.IsMap()) {
    for (auto it = node.begin(); it != node.end(); ++it) make_numbers_readable(it->second);
  } else if (node.IsSequence()) {
    for (auto child : node) make_numbers_readable(child);
  } else if (node.IsScalar()) {
    // A number emrm or yaml-cpp wrote: its shortest exact form, or yaml-cpp's 17 digits.
    const std::string text = node.Scalar();
    const auto value = parse_finite_number(text);
    if (value && (fmt::format("{}", *value) == text || fmt::format("{:.17g}", *value) == text))
      node = readable_number(*value);
  }
}
}  // namespace

std::string readable_yaml(const std::string& text) {
  try {
    YAML::Node root = YAML::Load(text);
    make_numbers_readable(root);
    return to_yaml_text(root);
  } catch (const YAML::Exception&) {
    return text;
  }
}

}  // namespace emrm::core
