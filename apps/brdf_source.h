// "Which BRDF" for render and synth commands: a MERL file, a stand-in or NBRDF
// material by name, or a weight vector from a fit over a database.
#pragma once

#include <boost/program_options.hpp>
#include <string>
#include <vector>

#include "apps/common_options.h"
#include "fit/merl_brdf.h"

namespace brdfshot {

// One BRDF named on the command line: the option ("merl", "standin",
// "nbrdf" or "weights") and its value.
struct BrdfSource {
  std::string option, value;
};

struct BrdfSourceArgs {
  std::vector<std::string> merl, standin, nbrdf, weights;
  // `several`: each option may be given more than once (render's BRDFs).
  void Add(boost::program_options::options_description& d, bool several = false);
  // Every source given, in command-line order (`given`: ParseOptions' names
  // of the options in that order).
  std::vector<BrdfSource> Given(const std::vector<std::string>& given) const;
  // Exactly one source must be given; the grid comes from `db` for named materials.
  MerlBrdf Load(const DatabaseArgs& db, std::string* label) const;
  static MerlBrdf Load(const BrdfSource& source, const DatabaseArgs& db, std::string* label);
  // The given source as command-line options ("--nbrdf red-plastic --grid
  // 90x90x180"), with the data folder and file paths made absolute: how a
  // capture folder records its true material, renderable from anywhere
  // whatever database a fit uses.
  std::string ToArgs(const DatabaseArgs& db) const;

 private:
  BrdfSource One() const;  // the one source given, or an error
};

}  // namespace brdfshot
