// The fit stage on files: basis images + the photo's pixels + the class model
// → fit.json (FitRecord), brdf.binary (the fitted BRDF in MERL's format) and
// pictures: the photo beside its reconstruction, and the result relit under
// other probes.
#pragma once

#include <string>
#include <vector>

#include "fit/database.h"
#include "fit/photo_fit.h"
#include "fit/transport.h"

namespace brdfshot {

struct FitStageOptions {
  // One photo, or several of the same material fitted jointly (JointPhotos):
  // per photo its basis-image cache and either a linear HDR photo aligned
  // with the basis images' pixels or the observation file they were rendered
  // for (`photo` or `observations` empty, the other as long as `basis`).
  std::vector<std::string> basis;
  std::vector<std::string> photo;
  std::vector<std::string> observations;
  std::string classes;       // class model
  std::string out;           // output folder (made once the inputs have been read)
  PhotoFitOptions fit;
  DatabaseOptions database;                 // where the bases' tables come from
  std::vector<std::string> preview_probes;  // relight under up to two of these (not the basis images' own probe)
  RenderQuality preview_quality;
};

struct FitStageResult {
  FitRecord record;
  std::string label;  // what the BRDF is
  long clamped = 0;   // bin-channels of the written table raised to zero from below
  std::vector<std::string> previews;
};

// Errors name the file: a class model for other bases, pixels that are not
// the basis images', a database without the bases' tables. A refused input
// leaves no output folder behind.
FitStageResult RunFitStage(const FitStageOptions& options);

}  // namespace brdfshot
