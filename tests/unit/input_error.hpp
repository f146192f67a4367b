#pragma once

// The InputError a piece of bad input must raise, for tests that then check its message and
// location. Any other outcome is a test failure (and a placeholder error is returned).

#include <gtest/gtest.h>

#include <exception>
#include <string>

#include "emrm/core/error.hpp"

namespace emrm::testing {

template <class Load>
[[nodiscard]] InputError input_error_of(Load&& load, const std::string& input) {
  try {
    load();
  } catch (const InputError& e) {
    return e;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected an InputError, got: " << e.what() << "\nfor:\n" << input;
    return InputError({}, "none");
  }
  ADD_FAILURE() << "expected an InputError for:\n" << input;
  return InputError({}, "none");
}

}  // namespace emrm::testing
