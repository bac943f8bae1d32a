#include "fit/database.h"

#include <algorithm>
#include <filesystem>
#include <cstdio>
#include <fstream>
#include <functional>

#include "fit/database_cache.h"
#include "fit/standin.h"
#include "util/check.h"
#include "util/data_paths.h"
#include "util/huge_pages.h"
#include "util/progress.h"

namespace brdfshot {
namespace fs = std::filesystem;

std::string BasisName(const std::vector<std::string>& materials, int col) {
  static const char* kCh[3] = {"R", "G", "B"};
  return materials.at(col / 3) + "/" + kCh[col % 3];
}

std::string BasisDatabase::BasisName(int col) const { return brdfshot::BasisName(materials, col); }

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
  for (size_t i = 0; i < basis_names.size(); i += 3) out.push_back(basis_names[i].substr(0, basis_names[i].rfind('/')));
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
void StoreColumns(MatrixXfR* B, int m, const MerlBrdf& brdf) {
  for (size_t idx = 0; idx < brdf.grid().size(); ++idx)
    for (int c = 0; c < 3; ++c) {
      const double v = brdf.Value(c, idx);
      (*B)(idx, 3 * m + c) = v < 0 ? 0.0f : static_cast<float>(v);
    }
}
}  // namespace

namespace {
bool Exists(const std::string& p) {
  std::error_code ec;
  return !p.empty() && fs::exists(p, ec);
}

// The data root's copy when it has one, else the repository's own.
std::string NbrdfFolder(const DatabaseOptions& opt) {
  const std::string shared = DataPath("merl-nbrdf", opt.data_root);
  return Exists(shared + "/materials.txt") ? shared : RepoDataPath("merl-nbrdf");
}
std::string StandinFolder(const DatabaseOptions& opt) {
  const std::string shared = DataPath("standin", opt.data_root);
  return Exists(shared + "/materials.tsv") ? shared : AssetPath("standin");
}
}  // namespace

std::string ResolveDatabaseKind(const DatabaseOptions& opt, std::string* folder) {
  const std::string merl = !opt.merl_dir.empty() ? opt.merl_dir : DataPath("merl", opt.data_root);
  const std::string nbrdf = NbrdfFolder(opt), standin = StandinFolder(opt);
  if ((opt.kind == "auto" || opt.kind == "merl") && !MerlFiles(merl).empty()) {
    *folder = merl;
    return "merl";
  }
  if (opt.kind == "merl")
    throw Error("no MERL .binary files in '" + merl + "' (set --merl-dir or BRDFSHOT_DATA; see README 'Data')");
  if ((opt.kind == "auto" || opt.kind == "nbrdf") && Exists(nbrdf + "/materials.txt")) {
    *folder = nbrdf;
    return "nbrdf";
  }
  if (opt.kind == "nbrdf")
    throw Error("no merl-nbrdf/materials.txt under the data folder '" + DataRoot(opt.data_root) +
                "' nor in the repository's data/ folder");
  if ((opt.kind == "auto" || opt.kind == "standin") && Exists(standin + "/materials.tsv")) {
    *folder = standin;
    return "standin";
  }
  if (opt.kind != "auto" && opt.kind != "standin")
    throw Error("unknown database kind '" + opt.kind + "' (auto, merl, nbrdf, standin)");
  throw Error(
      "no BRDF database found: set BRDFSHOT_DATA to a folder with merl/, merl-nbrdf/ or "
      "standin/ (see README 'Data'); looked in '" +
      DataRoot(opt.data_root) + "'");
}

namespace {
// B is 1.7 GB for the full grid, and the basis images read its rows all over
// the table: with 2 MB pages the operator's table gathers ran ~25 % faster
// and filling B faulted 512× fewer pages (util/huge_pages.h).
MatrixXfR AllocateBasisMatrix(const MerlGrid& grid, size_t cols) {
  MatrixXfR B(static_cast<Eigen::Index>(grid.size()), static_cast<Eigen::Index>(cols));
  AdviseHugePages(B.data(), sizeof(float) * B.size());
  return B;
}

// A computed database (nbrdf or stand-in): its materials and the files it is made of.
struct ComputedSource {
  std::string kind, folder;
  std::vector<std::string> names, families;
  std::vector<StandinMaterial> standin;
  std::vector<std::string> files;  // what the tables are computed from (the cache's fingerprint)
};

ComputedSource ReadComputedSource(const std::string& kind, const std::string& folder) {
  ComputedSource s;
  s.kind = kind;
  s.folder = folder;
  if (kind == "nbrdf") {
    s.files.push_back(folder + "/materials.txt");
    s.names = ReadLines(s.files[0]);
    for (const auto& n : s.names)
      for (const char* suffix : {"_fc1", "_b1", "_fc2", "_b2", "_fc3", "_b3"})
        s.files.push_back(folder + "/npy/" + n + suffix + ".npy");
  } else {
    s.files.push_back(folder + "/materials.tsv");
    s.standin = ReadStandinTable(s.files[0]);
    for (const auto& m : s.standin) s.names.push_back(m.name), s.families.push_back(m.family);
  }
  return s;
}

BasisDatabase ComputeTables(const ComputedSource& src, const MerlGrid& grid, const std::vector<int>& keep,
                            bool progress_on) {
  BasisDatabase db;
  db.kind = src.kind;
  db.grid = grid;
  for (int k : keep) {
    db.materials.push_back(src.names[k]);
    if (!src.families.empty()) db.families.push_back(src.families[k]);
  }
  MatrixXfR B = AllocateBasisMatrix(db.grid, 3 * keep.size());
  if (src.kind == "nbrdf") {
    db.label = "MERL (NBRDF approximation)";
    const MatrixXfR x = NbrdfInputs(db.grid);
    const std::vector<float> cosw = db.grid.CosineWeightTable();  // > 0 where measurable
    std::vector<NbrdfNetwork> nets;
    for (int k : keep) nets.push_back(NbrdfNetwork::Load(src.folder + "/npy", src.names[k]));
    Progress progress("evaluating NBRDF", keep.size(), progress_on);
#pragma omp parallel for schedule(dynamic, 1)
    for (int m = 0; m < static_cast<int>(keep.size()); ++m) {
      const MatrixXfR rho = nets[m].Eval(x);
      for (size_t idx = 0; idx < db.grid.size(); ++idx)
        for (int c = 0; c < 3; ++c) B(idx, 3 * m + c) = cosw[idx] > 0 ? rho(idx, c) : 0.0f;
      progress.Step();
    }
    db.B = BasisTables(std::move(B));
    return db;
  }
  db.label = "stand-in (analytic)";
  Progress progress("sampling stand-in", keep.size(), progress_on);
#pragma omp parallel for schedule(dynamic, 1)
  for (int m = 0; m < static_cast<int>(keep.size()); ++m) {
    StoreColumns(&B, m, src.standin[keep[m]].ToMerl(db.grid));
    progress.Step();
  }
  db.B = BasisTables(std::move(B));
  return db;
}

// Bump when the evaluation of a computed table changes, so older caches read as stale.
constexpr const char* kTablesVersion = "tables-1";

CachedDatabaseId CacheId(const ComputedSource& src, const MerlGrid& grid) {
  return {src.kind, grid, FingerprintFiles(src.files, std::string(kTablesVersion) + "/" + src.kind)};
}

std::vector<int> AllIndices(size_t n) {
  std::vector<int> all(n);
  for (size_t i = 0; i < n; ++i) all[i] = static_cast<int>(i);
  return all;
}

// Reads what the caller needs from the cache file for `src` (`read` throws
// Error on a file that is not a sound cache); when the file is missing, stale
// or damaged, computes every material into `built` and writes the cache.
// Returns the cache's path, or "" when caching is off or the cache folder
// cannot be written (then `built` holds the tables, or nothing with caching off).
std::string EnsureCache(const ComputedSource& src, const DatabaseOptions& opt, const CachedDatabaseId& id,
                        const std::function<void(const std::string&)>& read, BasisDatabase* built) {
  const std::string dir = opt.use_cache ? CacheDir() : "";
  if (dir.empty()) return "";
  const std::string path = (fs::path(dir) / id.FileName()).string();
  if (Exists(path)) {
    try {
      read(path);
      return path;
    } catch (const Error& e) {
      std::fprintf(stderr, "warning: %s; rebuilding the database cache\n", e.what());
    }
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  Stopwatch sw;
  *built = ComputeTables(src, opt.grid, AllIndices(src.names.size()), opt.progress);
  const std::vector<float> cosw = built->grid.CosineWeightTable();
  try {
    WriteDatabaseCache(path, id, *built, GramMatrix(built->B), GramMatrix(built->B, &cosw));
  } catch (const Error& e) {
    std::fprintf(stderr, "warning: cannot write the database cache (%s); computing without it\n", e.what());
    return "";
  }
  std::fprintf(stderr, "built the database cache %s (%s, %zu materials) in %.1f s\n", path.c_str(),
               built->label.c_str(), src.names.size(), sw.Seconds());
  return path;
}

BasisDatabase SelectColumns(BasisDatabase full, const std::vector<int>& keep) {
  if (keep == AllIndices(full.materials.size())) return full;
  BasisDatabase db;
  db.kind = full.kind;
  db.label = full.label;
  db.grid = full.grid;
  std::vector<int> cols;
  for (int m : keep) {
    db.materials.push_back(full.materials[m]);
    if (!full.families.empty()) db.families.push_back(full.families[m]);
    for (int c = 0; c < 3; ++c) cols.push_back(3 * m + c);
  }
  MatrixXfR B = AllocateBasisMatrix(db.grid, cols.size());
#pragma omp parallel for schedule(static)
  for (long r = 0; r < static_cast<long>(B.rows()); ++r)
    for (size_t k = 0; k < cols.size(); ++k) B(r, k) = full.B(r, cols[k]);
  db.B = BasisTables(std::move(B));
  return db;
}

BasisDatabase LoadMerlFiles(const std::string& folder, const DatabaseOptions& opt) {
  BasisDatabase db;
  db.kind = "merl";
  const std::vector<std::string> files = MerlFiles(folder);
  std::vector<std::string> names;
  for (const auto& f : files) names.push_back(fs::path(f).stem().string());
  const std::vector<int> keep = SelectMaterials(names, opt);
  db.label = "MERL";
  MatrixXfR B;
  Progress progress("reading MERL", keep.size(), opt.progress);
  for (size_t m = 0; m < keep.size(); ++m) {
    const MerlBrdf brdf = MerlBrdf::Read(files[keep[m]]);
    if (m == 0) {
      db.grid = brdf.grid();
      B = AllocateBasisMatrix(db.grid, 3 * keep.size());
    } else if (!(brdf.grid() == db.grid)) {
      throw FileError(files[keep[m]], "grid differs from the other MERL files");
    }
    db.materials.push_back(names[keep[m]]);
    StoreColumns(&B, static_cast<int>(m), brdf);
    progress.Step();
  }
  db.B = BasisTables(std::move(B));
  return db;
}
}  // namespace

BasisDatabase LoadDatabase(const DatabaseOptions& opt) {
  std::string folder;
  const std::string kind = ResolveDatabaseKind(opt, &folder);
  // Real MERL files are read as they are: parsing them is the whole cost.
  if (kind == "merl") return LoadMerlFiles(folder, opt);
  const ComputedSource src = ReadComputedSource(kind, folder);
  const std::vector<int> keep = SelectMaterials(src.names, opt);
  const CachedDatabaseId id = CacheId(src, opt.grid);
  BasisDatabase cached, built;
  EnsureCache(
      src, opt, id, [&](const std::string& p) { cached = ReadDatabaseCache(p, id, keep); }, &built);
  if (!cached.materials.empty()) return cached;
  if (!built.materials.empty()) return SelectColumns(std::move(built), keep);  // just built, all materials
  return ComputeTables(src, opt.grid, keep, opt.progress);                     // caching off
}

DatabaseGrams LoadDatabaseGrams(const DatabaseOptions& opt) {
  std::string folder;
  const std::string kind = ResolveDatabaseKind(opt, &folder);
  auto from_tables = [](const BasisDatabase& db) {
    DatabaseGrams g{db.kind, db.label, db.grid, db.materials, db.families, GramMatrix(db.B), {}};
    const std::vector<float> cosw = db.grid.CosineWeightTable();
    g.gram_cos = GramMatrix(db.B, &cosw);
    return g;
  };
  if (kind == "merl") return from_tables(LoadMerlFiles(folder, opt));
  const ComputedSource src = ReadComputedSource(kind, folder);
  const std::vector<int> keep = SelectMaterials(src.names, opt);
  const CachedDatabaseId id = CacheId(src, opt.grid);
  DatabaseGrams grams;
  BasisDatabase built;
  const std::string path = EnsureCache(
      src, opt, id, [&](const std::string& p) { grams = ReadDatabaseCacheGrams(p, id, keep); }, &built);
  if (!grams.materials.empty()) return grams;
  if (!path.empty()) return ReadDatabaseCacheGrams(path, id, keep);  // just built
  return from_tables(ComputeTables(src, opt.grid, keep, opt.progress));
}

Eigen::MatrixXd GramMatrix(const TablesRef& B, const std::vector<float>* w, TableMapping mapping) {
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
      if (mapping == TableMapping::kLog) blk = blk.array().max(0.0f).log1p().matrix();
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

MerlBrdf CombineBases(const BasisDatabase& db, const Eigen::MatrixXd& weights, long* clamped) {
  BRDFSHOT_CHECK(weights.rows() == db.num_bases() && weights.cols() == 3);
  MerlBrdf out(db.grid);
  const Eigen::MatrixXf wf = weights.cast<float>();
  const std::vector<float> cosw = db.grid.CosineWeightTable();  // > 0 where measurable
  long below = 0;
#pragma omp parallel for schedule(static) reduction(+ : below)
  for (long idx = 0; idx < static_cast<long>(db.grid.size()); ++idx) {
    if (!(cosw[idx] > 0)) continue;
    for (int c = 0; c < 3; ++c) {
      const double v = db.B.row(idx).dot(wf.col(c).transpose());
      // A combination may dip below zero where weights are negative: clamp, since
      // a negative entry would read as "unmeasured".
      below += v < 0;
      out.set_raw(c, idx, std::max(0.0, v) / kMerlScale[c]);
    }
  }
  if (clamped) *clamped = below;
  return out;
}

}  // namespace brdfshot
