// brdfshot cluster: the class model of a database (paper sec. 3).
#include <cstdio>
#include <fstream>

#include "apps/command.h"
#include "apps/common_options.h"
#include "fit/class_model.h"
#include "util/plots.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"
#include "util/progress.h"

namespace brdfshot {
namespace po = boost::program_options;

int ClusterMain(int argc, char** argv) {
  DatabaseArgs db;
  GmmOptions gmm;
  std::string out = "classes.json", plot;
  po::options_description desc("options");
  // clang-format off
  desc.add_options()
      ("out,o", po::value(&out)->default_value(out), "class model (JSON)")
      ("plot", po::value(&plot), "MDS picture of the classes (PNG; default: <out>.png)")
      ("dims", po::value(&gmm.dims)->default_value(gmm.dims), "SVD coordinates kept (paper: N = 4)")
      ("classes", po::value(&gmm.classes)->default_value(gmm.classes), "Gaussians (paper: K = 4)")
      ("seed", po::value(&gmm.seed)->default_value(gmm.seed), "k-means seed")
      ("reg", po::value(&gmm.reg)->default_value(gmm.reg), "covariance ridge (relative)")
      ("paper-mstep", po::bool_switch(&gmm.paper_mstep), "use the paper's printed M-step (divide by pi_j)");
  // clang-format on
  db.Add(desc);
  if (!ParseOptions("cluster", "[options]", desc, argc, argv)) return 0;
  if (plot.empty()) plot = out.substr(0, out.rfind('.')) + ".png";

  Stopwatch sw;
  // The class model needs only BᵀB, which the database cache keeps.
  const DatabaseGrams base = LoadDatabaseGrams(db.ToOptions(true));
  const double t_load = sw.Seconds();
  ClassModel model = BuildClassModel(base.gram, gmm);
  const double t_em = sw.Seconds() - t_load;
  const int num_bases = static_cast<int>(base.gram.rows());

  for (int i = 0; i < num_bases; ++i) model.basis_names.push_back(BasisName(base.materials, i));
  model.database = base.label;
  model.grid = {base.grid.n_th, base.grid.n_td, base.grid.n_pd};
  model.Write(out);

  std::vector<std::string> labels(num_bases);
  for (size_t m = 0; m < base.materials.size(); ++m) labels[3 * m + 1] = base.materials[m];
  WritePng(plot, ScatterPlot(ClassicalMds2(model.coords), model.label, labels,
                             "MDS of the " + std::to_string(gmm.dims) + "-D class coordinates, " + base.label +
                                 " (classes " + ClassSizes(model) + ")"));
  std::printf("database: %s, %d bases\n", base.label.c_str(), num_bases);
  std::printf("class sizes: %s   (paper, real MERL: 137 / 99 / 24 / 40)\n", ClassSizes(model).c_str());
  for (int k = 0; k < model.classes(); ++k) {
    std::printf("  class %d (%zu):", k, model.Members(k).size());
    int shown = 0;
    for (int i : model.Members(k))
      if (i % 3 == 1 && shown++ < 8) std::printf(" %s", base.materials[i / 3].c_str());
    std::printf("%s\n", shown > 8 ? " ..." : "");
  }
  std::printf("EM: %d iterations, converged=%s, log-likelihood %.6g\n", model.iterations,
              model.converged ? "yes" : "no", model.log_likelihood);
  std::printf("time: database Gram matrix %.2f s, SVD+EM %.3f s\nwrote %s and %s\n", t_load, t_em, out.c_str(),
              plot.c_str());
  return 0;
}

}  // namespace brdfshot
