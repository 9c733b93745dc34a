// The suite runner's errors.
#pragma once

#include <stdexcept>

namespace ovpc::suite {

/// Bad input given by the user (arguments, files, an output folder that cannot be used): one line,
/// exit code 2. A std::invalid_argument, as the Configs' Validate() errors are.
class BadInput : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace ovpc::suite
