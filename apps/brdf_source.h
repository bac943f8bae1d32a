// "Which BRDF" for render and synth commands: a MERL file, a stand-in or NBRDF
// material by name, or a weight vector from a fit over a database.
#pragma once

#include <boost/program_options.hpp>
#include <string>

#include "apps/common_options.h"
#include "fit/merl_brdf.h"

namespace brdfshot {

struct BrdfSourceArgs {
  std::string merl, standin, nbrdf, weights;
  void Add(boost::program_options::options_description& d);
  // Exactly one source must be given; the grid comes from `db` for named materials.
  MerlBrdf Load(const DatabaseArgs& db, std::string* label) const;
  // The given source as command-line options ("--nbrdf red-plastic --grid
  // 90x90x180"), with the data folder and file paths made absolute: how a
  // capture folder records its true material, renderable from anywhere
  // whatever database a fit uses.
  std::string ToArgs(const DatabaseArgs& db) const;
};

}  // namespace brdfshot
