#include "fit/database.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "fit/standin.h"
#include "util/check.h"
#include "util/data_paths.h"
#include "util/huge_pages.h"
#include "util/progress.h"

namespace brdfshot {
namespace fs = std::filesystem;

std::string BasisDatabase::BasisName(int col) const {
  static const char* kCh[3] = {"R", "G", "B"};
  return materials.at(col / 3) + "/" + kCh[col % 3];
}

namespace {
std::vector<std::string> MerlFiles(const std::string& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return files;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".binary") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}
}  // namespace

std::vector<std::string> ReadLines(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw FileError(path, "cannot open material list");
  std::vector<std::string> out;
  std::string s;
  while (std::getline(in, s))
    if (!s.empty()) out.push_back(s);
  return out;
}

std::vector<std::string> MaterialsOfBases(const std::vector<std::string>& basis_names) {
  std::vector<std::string> out;
  for (size_t i = 0; i < basis_names.size(); i += 3)
    out.push_back(basis_names[i].substr(0, basis_names[i].rfind('/')));
  return out;
}

std::vector<int> SelectMaterials(const std::vector<std::string>& names, const DatabaseOptions& opt) {
  std::vector<int> keep;
  if (!opt.only.empty()) {
    for (const auto& want : opt.only) {
      auto it = std::find(names.begin(), names.end(), want);
      if (it == names.end()) throw Error("material '" + want + "' is not in the database");
      keep.push_back(static_cast<int>(it - names.begin()));
    }
  } else {
    for (int i = 0; i < static_cast<int>(names.size()); ++i) keep.push_back(i);
  }
  for (const auto& drop : opt.exclude) {
    auto it = std::find(names.begin(), names.end(), drop);
    if (it == names.end()) throw Error("excluded material '" + drop + "' is not in the database");
    keep.erase(std::remove(keep.begin(), keep.end(), static_cast<int>(it - names.begin())), keep.end());
  }
  if (opt.max_materials > 0 && static_cast<int>(keep.size()) > opt.max_materials) {
    std::vector<int> spread;
    for (int i = 0; i < opt.max_materials; ++i)
      spread.push_back(keep[static_cast<size_t>(i) * keep.size() / opt.max_materials]);
    keep = spread;
  }
  return keep;
}

namespace {
void StoreColumns(BasisDatabase* db, int m, const MerlBrdf& brdf) {
  for (size_t idx = 0; idx < db->grid.size(); ++idx)
    for (int c = 0; c < 3; ++c) {
      const double v = brdf.Value(c, idx);
      db->B(idx, 3 * m + c) = v < 0 ? 0.0f : static_cast<float>(v);
    }
}
}  // namespace

std::string ResolveDatabaseKind(const DatabaseOptions& opt, std::string* folder) {
  const std::string merl = !opt.merl_dir.empty() ? opt.merl_dir : DataPath("merl", opt.data_root);
  const std::string nbrdf = DataPath("merl-nbrdf", opt.data_root);
  const std::string standin = DataPath("standin", opt.data_root);
  auto has = [](const std::string& p) {
    std::error_code ec;
    return !p.empty() && fs::exists(p, ec);
  };
  if ((opt.kind == "auto" || opt.kind == "merl") && !MerlFiles(merl).empty()) {
    *folder = merl;
    return "merl";
  }
  if (opt.kind == "merl")
    throw Error("no MERL .binary files in '" + merl +
                "' (set --merl-dir or BRDFSHOT_DATA; see README 'Data')");
  if ((opt.kind == "auto" || opt.kind == "nbrdf") && has(nbrdf + "/materials.txt")) {
    *folder = nbrdf;
    return "nbrdf";
  }
  if (opt.kind == "nbrdf") throw Error("no merl-nbrdf/materials.txt under the data folder '" + DataRoot(opt.data_root) + "'");
  if ((opt.kind == "auto" || opt.kind == "standin") && has(standin + "/materials.tsv")) {
    *folder = standin;
    return "standin";
  }
  if (opt.kind != "auto" && opt.kind != "standin")
    throw Error("unknown database kind '" + opt.kind + "' (auto, merl, nbrdf, standin)");
  throw Error("no BRDF database found: set BRDFSHOT_DATA to a folder with merl/, merl-nbrdf/ or "
              "standin/ (see README 'Data'); looked in '" + DataRoot(opt.data_root) + "'");
}

namespace {
// B is 1.7 GB for the full grid, and the basis images read its rows all over
// the table: with 2 MB pages the operator's table gathers ran ~25 % faster
// and filling B faulted 512× fewer pages (util/huge_pages.h).
void AllocateBasisMatrix(BasisDatabase* db, size_t cols) {
  db->B.resize(static_cast<Eigen::Index>(db->grid.size()), static_cast<Eigen::Index>(cols));
  AdviseHugePages(db->B.data(), sizeof(float) * db->B.size());
}
}  // namespace

BasisDatabase LoadDatabase(const DatabaseOptions& opt) {
  std::string folder;
  BasisDatabase db;
  db.kind = ResolveDatabaseKind(opt, &folder);
  if (db.kind == "merl") {
    const std::vector<std::string> files = MerlFiles(folder);
    std::vector<std::string> names;
    for (const auto& f : files) names.push_back(fs::path(f).stem().string());
    const std::vector<int> keep = SelectMaterials(names, opt);
    db.label = "MERL";
    Progress progress("reading MERL", keep.size(), opt.progress);
    for (size_t m = 0; m < keep.size(); ++m) {
      const MerlBrdf brdf = MerlBrdf::Read(files[keep[m]]);
      if (m == 0) {
        db.grid = brdf.grid();
        AllocateBasisMatrix(&db, 3 * keep.size());
      } else if (!(brdf.grid() == db.grid)) {
        throw FileError(files[keep[m]], "grid differs from the other MERL files");
      }
      db.materials.push_back(names[keep[m]]);
      StoreColumns(&db, static_cast<int>(m), brdf);
      progress.Step();
    }
    return db;
  }
  db.grid = opt.grid;
  if (db.kind == "nbrdf") {
    const std::vector<std::string> names = ReadLines(folder + "/materials.txt");
    const std::vector<int> keep = SelectMaterials(names, opt);
    db.label = "MERL (NBRDF approximation)";
    AllocateBasisMatrix(&db, 3 * keep.size());
    const MatrixXfR x = NbrdfInputs(db.grid);
    std::vector<char> measurable(db.grid.size());
    for (size_t i = 0; i < measurable.size(); ++i) measurable[i] = db.grid.Measurable(i);
    std::vector<NbrdfNetwork> nets;
    for (int k : keep) nets.push_back(NbrdfNetwork::Load(folder + "/npy", names[k]));
    Progress progress("evaluating NBRDF", keep.size(), opt.progress);
#pragma omp parallel for schedule(dynamic, 1)
    for (int m = 0; m < static_cast<int>(keep.size()); ++m) {
      const MatrixXfR rho = nets[m].Eval(x);
      for (size_t idx = 0; idx < db.grid.size(); ++idx)
        for (int c = 0; c < 3; ++c) db.B(idx, 3 * m + c) = measurable[idx] ? rho(idx, c) : 0.0f;
      progress.Step();
    }
    for (int k : keep) db.materials.push_back(names[k]);
    return db;
  }
  // Stand-in.
  const std::vector<StandinMaterial> table = ReadStandinTable(folder + "/materials.tsv");
  std::vector<std::string> names;
  for (const auto& m : table) names.push_back(m.name);
  const std::vector<int> keep = SelectMaterials(names, opt);
  db.label = "stand-in (analytic)";
  AllocateBasisMatrix(&db, 3 * keep.size());
  Progress progress("sampling stand-in", keep.size(), opt.progress);
#pragma omp parallel for schedule(dynamic, 1)
  for (int m = 0; m < static_cast<int>(keep.size()); ++m) {
    StoreColumns(&db, m, table[keep[m]].ToMerl(db.grid));
    progress.Step();
  }
  for (int k : keep) {
    db.materials.push_back(table[k].name);
    db.families.push_back(table[k].family);
  }
  return db;
}

Eigen::MatrixXd GramMatrix(const MatrixXfR& B, const std::vector<float>* w) {
  const Eigen::Index n = B.cols();
  constexpr Eigen::Index kBlock = 8192;
  const Eigen::Index blocks = (B.rows() + kBlock - 1) / kBlock;
  Eigen::MatrixXd total = Eigen::MatrixXd::Zero(n, n);
#pragma omp parallel
  {
    Eigen::MatrixXd local = Eigen::MatrixXd::Zero(n, n);
    Eigen::MatrixXf blk;
#pragma omp for schedule(dynamic, 4)
    for (Eigen::Index b = 0; b < blocks; ++b) {
      const Eigen::Index r0 = b * kBlock, rows = std::min(kBlock, B.rows() - r0);
      blk = B.middleRows(r0, rows);
      if (w)
        for (Eigen::Index r = 0; r < rows; ++r) blk.row(r) *= (*w)[r0 + r];
      // Within a block float is exact enough (≤ 8192 terms); blocks add in double.
      Eigen::MatrixXf g = Eigen::MatrixXf::Zero(n, n);
      g.selfadjointView<Eigen::Lower>().rankUpdate(blk.transpose());
      local += g.cast<double>();
    }
#pragma omp critical
    total += local;
  }
  return total.selfadjointView<Eigen::Lower>();
}

std::vector<float> CosineWeights(const MerlGrid& grid) {
  std::vector<float> w(grid.size());
#pragma omp parallel for schedule(static)
  for (long i = 0; i < static_cast<long>(grid.size()); ++i)
    w[i] = static_cast<float>(grid.CosineWeight(i));
  return w;
}

MerlBrdf CombineBases(const BasisDatabase& db, const Eigen::MatrixXd& weights) {
  BRDFSHOT_CHECK(weights.rows() == db.num_bases() && weights.cols() == 3);
  MerlBrdf out(db.grid);
  const Eigen::MatrixXf wf = weights.cast<float>();
#pragma omp parallel for schedule(static)
  for (long idx = 0; idx < static_cast<long>(db.grid.size()); ++idx) {
    if (!db.grid.Measurable(idx)) continue;
    for (int c = 0; c < 3; ++c) {
      const double v = db.B.row(idx).dot(wf.col(c).transpose());
      // A combination may dip below zero where weights are negative: clamp, since
      // a negative entry would read as "unmeasured".
      out.set_raw(c, idx, std::max(0.0, v) / kMerlScale[c]);
    }
  }
  return out;
}

}  // namespace brdfshot
