// brdfshot merge-check: how good a merge of a real bracket is, without ground
// truth — each inner frame left out and predicted from the others, ours beside
// OpenCV's Debevec merge, and the shadows' chroma speckle
// (capture/merge_quality.h).
#include <cstdio>

#include "apps/command.h"
#include "capture/bracket.h"
#include "capture/merge_quality.h"
#include "util/atomic_file.h"

namespace brdfshot {
namespace po = boost::program_options;

int MergeCheckMain(int argc, char** argv) {
  std::vector<std::string> inputs;
  std::string out;
  BracketReadOptions read;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("input", po::value(&inputs)->multitoken(), "8-bit frames: files or a folder (positional)")
      ("times", po::value(&read.times_path), "exposure times file, one per frame in input order (overrides EXIF)")
      ("out,o", po::value(&out), "also write the table here (markdown)");
  // clang-format on
  po::positional_options_description pos;
  pos.add("input", -1);
  if (!ParseOptions("merge-check", "FRAME... | FOLDER [options]", desc, argc, argv, &pos)) return 0;
  read.progress = true;
  const Bracket b = ReadBracket(ExpandBracketInputs(inputs), read);
  CheckBracketMeasured(b);
  const std::string table = MergeCheckTable(CheckMerges(b.frames, b.exposure));
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
