#include "physics/errors.h"

#include <sstream>

namespace softwrist::physics {

void require(bool ok, std::string_view name, double value, std::string_view requirement) {
  if (ok) return;
  std::ostringstream message;
  message << name << " = " << value << ": " << requirement;
  throw InvalidParameter(message.str());
}

}  // namespace softwrist::physics
