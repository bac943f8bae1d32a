// EXIF orientation (TIFF tag 274): how a stored image must be turned to be
// seen upright. Values 1..8 as in the EXIF 2.3 standard, section 4.6.4.
#pragma once

#include <opencv2/core.hpp>

namespace brdfshot {

// The upright view of an image stored with `orientation`; unknown values
// (0, > 8) leave it as stored.
cv::Mat ApplyExifOrientation(const cv::Mat& stored, int orientation);

}  // namespace brdfshot
