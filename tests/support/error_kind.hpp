#pragma once
// The kind of the oer::Error an operation throws, for tests that check how a failure is
// classified; a test failure (and Internal) when it throws none.
#include <gtest/gtest.h>

#include <functional>

#include "oer/core/error.hpp"

namespace oer::testing {

inline ErrorKind kind_of_failure(const std::function<void()>& operation) {
    try {
        operation();
    } catch (const Error& error) {
        return error.kind();
    }
    ADD_FAILURE() << "no oer::Error thrown";
    return ErrorKind::Internal;
}

}  // namespace oer::testing
