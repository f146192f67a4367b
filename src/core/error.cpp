#include "emrm/core/error.hpp"

#include <fmt/format.h>

namespace emrm {

std::string SourceLocation::str() const {
  if (line <= 0) return file;
  if (column <= 0) return fmt::format("{}:{}", file, line);
  return fmt::format("{}:{}:{}", file, line, column);
}

InputError::InputError(SourceLocation where, std::string message)
    : Error(where.file.empty() ? fmt::format("error: {}", message)
                               : fmt::format("{}: error: {}", where.str(), message)),
      where_(std::move(where)),
      message_(std::move(message)) {}

}  // namespace emrm
