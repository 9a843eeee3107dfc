#pragma once
// vec({1, 2, 3}): an Eigen::VectorXd from a braced list, for parameter vectors in tests.

#include <Eigen/Core>
#include <algorithm>
#include <initializer_list>

namespace omnidso::test {

inline Eigen::VectorXd vec(std::initializer_list<double> values) {
  Eigen::VectorXd v(static_cast<int>(values.size()));
  std::copy(values.begin(), values.end(), v.data());
  return v;
}

}  // namespace omnidso::test
