#pragma once
// The message of the omnidso::Error a call throws, for tests that check what an error says.
#include <gtest/gtest.h>

#include <omnidso/core/error.hpp>
#include <string>

namespace omnidso::test {

// The message of the Error that fn throws; a test failure, and "", when it throws none.
template <typename Fn>
std::string errorMessage(Fn&& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no omnidso::Error";
  return "";
}

}  // namespace omnidso::test
