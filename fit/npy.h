// NumPy .npy (format 1.0) reader for little-endian float32 arrays in C order —
// exactly what the NBRDF weights are. Anything else is rejected with the file
// named, never reinterpreted.
#pragma once

#include <string>
#include <vector>

namespace brdfshot {

struct NpyArray {
  std::vector<size_t> shape;
  std::vector<float> data;
};

NpyArray ReadNpyFloat32(const std::string& path);
// Parses an in-memory .npy (used by the fuzzer); `name` labels errors.
NpyArray ParseNpyFloat32(const std::string& bytes, const std::string& name);

}  // namespace brdfshot
