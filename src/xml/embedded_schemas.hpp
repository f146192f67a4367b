#pragma once

// The ASAM XSD files compiled into the library (generated from schemas/ by CMake:
// cmake/embedded_schemas.cpp.in).

#include <string_view>
#include <vector>

namespace emrm::xml::detail {

struct EmbeddedSchemaFile {
  std::string_view path;  // under schemas/: "opendrive/OpenDRIVE_1.7/opendrive_17_core.xsd"
  std::string_view text;
};

const std::vector<EmbeddedSchemaFile>& embedded_schema_files();

}  // namespace emrm::xml::detail
