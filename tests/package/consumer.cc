#include <cstdio>

#include "physics/paper_parameters.h"
#include "physics/range_of_motion.h"

int main() {
  const auto flexor = softwrist::physics::paper::design_optimum_flexor();
  const auto limit = softwrist::physics::joint_limit(flexor, 137e3, 1.5707963267948966);
  if (!limit || *limit <= 0.0) return 1;
  std::printf("design flexor limit %.2f rad\n", *limit);
  return 0;
}
