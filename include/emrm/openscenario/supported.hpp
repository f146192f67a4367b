#pragma once

// The one table of the OpenSCENARIO subset emrm reads (docs/import.md renders it; a test checks
// that the page lists exactly this table). An element outside it is an InputError at the element:
// "<Element> is not supported (supported: ...)".

#include <span>
#include <string_view>

#include "emrm/core/error.hpp"

namespace emrm::openscenario {

/// One supported element: where it stands (the XSD choice it is a member of) and what of it is read.
struct SupportedElement {
  std::string_view choice;   ///< the enclosing XSD element whose children are a choice
  std::string_view element;  ///< the chosen child element
  std::string_view note;     ///< what is read of it, what is approximated
};

[[nodiscard]] std::span<const SupportedElement> supported_elements() noexcept;

/// Whether `element` is a supported member of `choice`'s alternatives.
[[nodiscard]] bool is_supported(std::string_view choice, std::string_view element) noexcept;

/// Throws InputError at `where`, "<element> is not supported in <choice> (supported: A, B)", unless
/// `element` is a supported member of `choice`.
void require_supported(std::string_view choice, std::string_view element, const SourceLocation& where);

}  // namespace emrm::openscenario
