// brdfshot merge-check: how good a merge of a real bracket is, without ground
// truth — each inner frame left out and predicted from the others, ours beside
// OpenCV's Debevec merge, and the shadows' chroma speckle
// (capture/merge_quality.h).
#include <cstdio>

#include "apps/command.h"
#include "capture/bracket.h"
#include "capture/merge_quality.h"
#include "util/atomic_file.h"
#include "util/check.h"

namespace brdfshot {
namespace po = boost::program_options;

int MergeCheckMain(int argc, char** argv) {
  std::vector<std::string> inputs;
  std::string out;
  int clip_reach = -1;
  BracketReadOptions read;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("input", po::value(&inputs)->multitoken(), "8-bit frames: files or a folder (positional)")
      ("times", po::value(&read.times_path), "exposure times file, one per frame in input order (overrides EXIF)")
      ("clip-reach", po::value(&clip_reach)->default_value(clip_reach),
       "our merge's: a frame does not count within N px of a pixel it clips in two channels (-1: each channel on "
       "its own, merge's default; see merge --clip-reach)")
      ("out,o", po::value(&out), "also write the table here (markdown)");
  // clang-format on
  po::positional_options_description pos;
  pos.add("input", -1);
  if (!ParseOptions("merge-check", "FRAME... | FOLDER [options]", desc, argc, argv, &pos)) return 0;
  read.progress = true;
  const Bracket b = ReadBracket(ExpandBracketInputs(inputs), read);
  CheckBracketMeasured(b);
  if (clip_reach < -1 || clip_reach > 64) throw Error("--clip-reach must be -1 … 64");
  const std::string table = MergeCheckTable(CheckMerges(b.frames, b.exposure, clip_reach));
  std::printf(
      "%zu frames, %dx%d: each inner frame predicted from the others (its mid-tones, codes 32 … 223 in every "
      "channel)\n\n%s",
      b.frames.size(), b.frames[0].cols, b.frames[0].rows, table.c_str());
  if (!out.empty()) {
    WriteFileAtomic(out, [&](std::ostream& o) { o << table; });
    std::printf("wrote %s\n", out.c_str());
  }
  return 0;
}

}  // namespace brdfshot
