// Order statistics shared by evaluations and benchmarks.
#pragma once

#include <vector>

namespace brdfshot {

// Median (mean of the two middle values for an even count; 0 when empty).
double Median(std::vector<double> v);

}  // namespace brdfshot
