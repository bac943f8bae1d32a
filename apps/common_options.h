// Options shared by several subcommands: where the database comes from, which
// grid and materials, which probe and pixel quality.
#pragma once

#include <boost/program_options.hpp>
#include <opencv2/core.hpp>
#include <string>

#include "fit/database.h"
#include "fit/lambda_choice.h"
#include "fit/solver.h"
#include "fit/transport.h"

namespace brdfshot {

struct DatabaseArgs {
  std::string kind = "auto", data, merl_dir, grid = "90x90x180", materials, exclude;
  int max_materials = 0;
  void Add(boost::program_options::options_description& d);
  DatabaseOptions ToOptions(bool progress) const;
};

MerlGrid ParseGrid(const std::string& text);  // "90x90x180"
// An image size "WIDTHxHEIGHT" given to `option`, each side ≥ `min_side`;
// Error quoting the option and its text otherwise.
cv::Size ParseImageSize(const std::string& text, const std::string& option, int min_side);
std::vector<std::string> SplitList(const std::string& text);  // "a,b,c"
// `count` comma-separated numbers given to `option` (e.g. "--wb", names "R,G,B");
// Error quoting the option and its text otherwise.
std::vector<double> ParseNumberList(const std::string& text, size_t count, const std::string& option,
                                    const std::string& names);

// A focal length in pixels from a 35 mm-equivalent one (EXIF
// FocalLengthIn35mmFilm: the 36 mm side of full frame maps to the photo's
// longer side), or `focal_px` itself when `focal_35mm` is 0. The options are
// --<prefix>focal-px and --<prefix>focal-35mm: Error naming them when negative
// or not finite.
double FocalLengthPx(double focal_px, double focal_35mm, cv::Size photo, const std::string& prefix = "");

// "0,0.01,0.1,1": λ values, each finite and ≥ 0; Error quoting the text otherwise.
std::vector<double> ParseLambdaGrid(const std::string& text);

// --max-condition, --noise-margin, --min-condition: the condition bound of
// the λ search (fit/lambda_choice.h), bound to `choice`.
void AddConditionBoundOptions(boost::program_options::options_description& d, LambdaChoiceOptions* choice);
// Error naming the option whose value is out of range.
void CheckConditionBound(const LambdaChoiceOptions& choice);

// "none", "weights" or "bins" (--constraint); Error quoting the text otherwise.
WeightConstraint::Kind ParseConstraint(const std::string& text);

struct QualityArgs {
  RenderQuality q;
  void Add(boost::program_options::options_description& d);
};

// Ensures a folder exists for outputs; Error naming it if it cannot be made.
void MakeOutputDir(const std::string& dir);

}  // namespace brdfshot
