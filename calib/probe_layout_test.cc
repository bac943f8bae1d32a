#include "calib/probe_layout.h"

#include <gtest/gtest.h>

#include "calib/test_probes.h"

namespace brdfshot {
namespace {

TEST(ProbeLayout, AngularMapRoundTripIsCloseOnASmoothProbe) {
  const LatLongProbe p = SmoothProbe(256);
  const LatLongProbe back = AngularMapToLatLong(LatLongToAngularMap(p, 512), 256);
  // The angular map's rim (+Z) squeezes a whole ring into one pixel circle:
  // compare away from it, i.e. directions within 150° of −Z.
  cv::Mat mask(128, 256, CV_8U);
  for (int r = 0; r < 128; ++r)
    for (int c = 0; c < 256; ++c)
      mask.at<uint8_t>(r, c) = p.DirectionAt(c + 0.5, r + 0.5).z < std::cos(kPi / 6) ? 1 : 0;
  EXPECT_LT(RelRmse(back.rgb(), p.rgb(), mask), 2e-3);
}

}  // namespace
}  // namespace brdfshot
