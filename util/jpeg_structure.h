// Whether a JPEG file holds its whole image. OpenCV's decoder (libjpeg) only
// warns on a file that ends early ("Premature end of JPEG file") and returns
// the image with the missing rows filled in grey: a frame cut short by an
// interrupted copy would enter a merge as if it were a darker exposure. So
// the file's markers are walked from its start to its end marker.
#pragma once

#include <string>

namespace brdfshot {

// Throws FileError naming the file when it does not start with a JPEG start
// marker, when a segment's length runs past the end, or when the file ends
// before the end-of-image marker. Bytes after that marker (maker trailers)
// are allowed; so are thumbnails inside EXIF segments, which the walk skips
// by their segment's length.
void CheckJpegComplete(const std::string& path);

// The same on bytes in memory; "" when complete, else what is wrong.
std::string JpegStructureProblem(const std::string& bytes);

}  // namespace brdfshot
