#include "physics/errors.h"

#include <sstream>

namespace softwrist::physics {

void fail_requirement(std::string_view name, double value, std::string_view requirement) {
  std::ostringstream message;
  message << name << " = " << value << ": " << requirement;
  throw InvalidParameter(message.str());
}

}  // namespace softwrist::physics
