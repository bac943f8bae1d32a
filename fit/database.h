// The basis database in one place: real MERL files if the data folder has them,
// else MERL's materials as neural fits, else the analytic stand-in. Every output
// carries `label` so no result on an approximation is mistaken for MERL's.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "fit/basis_tables.h"
#include "fit/merl_brdf.h"
#include "fit/nbrdf.h"

namespace brdfshot {

struct DatabaseOptions {
  std::string kind = "auto";         // auto | merl | nbrdf | standin
  std::string data_root;             // "" = $BRDFSHOT_DATA, then ../shared
  std::string merl_dir;              // overrides <root>/merl
  MerlGrid grid = MerlGrid::Full();  // for nbrdf / standin (MERL files carry their own)
  std::vector<std::string> only;     // material names to keep (empty = all)
  std::vector<std::string> exclude;  // material names to leave out (leave-one-out on a capture)
  int max_materials = 0;             // >0: that many, evenly spread over the list
  bool progress = false;
  // Keep computed tables (nbrdf, standin) in CacheDir() (fit/database_cache.h).
  bool use_cache = true;
};

struct BasisDatabase {
  std::string kind;   // merl | nbrdf | standin
  std::string label;  // "MERL" | "MERL (NBRDF approximation)" | "stand-in (analytic)"
  MerlGrid grid;
  std::vector<std::string> materials;
  std::vector<std::string> families;  // stand-in only (diffuse/plastic/metal/paint)
  // bins × 3·materials; column 3m + c is channel c of material m, ρ in 1/sr,
  // 0 where not measured (so it contributes nothing to a render). Read from
  // the cache, a view of the mapped file (fit/basis_tables.h).
  BasisTables B;

  int num_bases() const { return static_cast<int>(B.cols()); }
  int num_materials() const { return static_cast<int>(materials.size()); }
  std::string BasisName(int col) const;
};

// The Gram matrices of a database's bases, without its tables: all that the
// class model and the leave-one-out metrics need.
struct DatabaseGrams {
  std::string kind, label;
  MerlGrid grid;
  std::vector<std::string> materials, families;
  Eigen::MatrixXd gram;      // BᵀB
  Eigen::MatrixXd gram_cos;  // Bᵀ diag(cos²) B (the BRDF metric's weights)
};

// "material/R|G|B": the name of basis column `col` over `materials`.
std::string BasisName(const std::vector<std::string>& materials, int col);

// Resolves which database `opt.kind` means on this machine (auto → first found),
// returning the kind and the folder; Error saying where to get data if none.
std::string ResolveDatabaseKind(const DatabaseOptions& opt, std::string* folder);

// The tables of the selected materials. Computed kinds come from the cache when
// it holds them (a missing, stale or damaged cache is rebuilt, with a note on
// stderr saying why and how long it took).
BasisDatabase LoadDatabase(const DatabaseOptions& opt);
DatabaseGrams LoadDatabaseGrams(const DatabaseOptions& opt);

// Material names listed in a merl-nbrdf materials.txt.
std::vector<std::string> ReadLines(const std::string& path);

// Material names of basis names "material/C", once per material, in order.
std::vector<std::string> MaterialsOfBases(const std::vector<std::string>& basis_names);

// Indices of `names` that `opt.only` / `opt.exclude` / `opt.max_materials` keep,
// in order. Error naming a wanted or excluded material the database lacks.
std::vector<int> SelectMaterials(const std::vector<std::string>& names, const DatabaseOptions& opt);

// BᵀB (or Bᵀ diag(w²) B) in double, accumulated over float row blocks so the
// 1.46M-row matrix is streamed once.
// With kLog, the Gram matrix of log(1 + w·B) instead (entries below zero
// taken as zero): the mapping data-driven BRDF work applies before a PCA, so
// that a specular peak of thousands per steradian does not outweigh the rest
// of the table.
enum class TableMapping { kLinear, kLog };
Eigen::MatrixXd GramMatrix(const TablesRef& B, const std::vector<float>* row_weight = nullptr,
                           TableMapping mapping = TableMapping::kLinear);

// A BRDF from per-channel weights over the bases: ρ_c = B w_c (MERL file layout;
// unmeasurable bins −1). `weights` is n × 3.
MerlBrdf CombineBases(const BasisDatabase& db, const Eigen::MatrixXd& weights, long* clamped = nullptr);

}  // namespace brdfshot
