#include "fit/transport.h"

#include <algorithm>
#include <cmath>

#include "util/check.h"
#include "util/huge_pages.h"

namespace brdfshot {

std::string RenderQuality::Describe() const {
  return "theta=" + std::to_string(theta_samples) + ",phi=" + std::to_string(phi_samples) +
         ",probe=" + std::to_string(probe_width) + ",lights=" + std::to_string(max_lights) + "@" +
         std::to_string(light_grid_width) + ",level_step=" + std::to_string(level_step_deg) +
         ",substeps=" + std::to_string(level_substeps) + ",brdf_supersample=" + std::to_string(brdf_supersample);
}

std::vector<DirectionalLight> ExtractLights(LatLongProbe* probe, int max_lights, double min_share, int grid_width) {
  std::vector<DirectionalLight> lights;
  if (max_lights <= 0) return lights;
  // Blocks of b×b texels, so that a sun counts as one light whatever the
  // probe's resolution: on a 1024-wide probe a sun spread over four texels
  // would otherwise leave each below the share and stay in the quadrature.
  const int b = grid_width > 0 ? std::max(1, probe->width() / grid_width) : 1;
  const int bw = (probe->width() + b - 1) / b, bh = (probe->height() + b - 1) / b;
  struct Block {
    double power = 0;
    int index = 0;
  };
  std::vector<Block> blocks(static_cast<size_t>(bw) * bh);
  double total = 0;
  for (int r = 0; r < probe->height(); ++r)
    for (int c = 0; c < probe->width(); ++c) {
      const cv::Vec3f v = probe->Texel(c, r);
      const double p = (v[0] + v[1] + v[2]) * probe->TexelSolidAngle(r);
      total += p;
      blocks[static_cast<size_t>(r / b) * bw + c / b].power += p;
    }
  if (total <= 0) return lights;
  for (size_t i = 0; i < blocks.size(); ++i) blocks[i].index = static_cast<int>(i);
  const size_t k = std::min<size_t>(max_lights, blocks.size());
  std::partial_sort(blocks.begin(), blocks.begin() + k, blocks.end(),
                    [](const Block& x, const Block& y) { return x.power > y.power; });
  cv::Mat rgb = probe->rgb().clone();
  for (size_t i = 0; i < k && blocks[i].power >= min_share * total; ++i) {
    // One light at the block's power centroid, carrying all of its power.
    const int r0 = blocks[i].index / bw * b, c0 = blocks[i].index % bw * b;
    Vec3 centroid(0, 0, 0);
    cv::Vec3f power(0, 0, 0);
    for (int r = r0; r < std::min(r0 + b, probe->height()); ++r)
      for (int c = c0; c < std::min(c0 + b, probe->width()); ++c) {
        const cv::Vec3f v = probe->Texel(c, r) * static_cast<float>(probe->TexelSolidAngle(r));
        centroid = centroid + probe->DirectionAt(c + 0.5, r + 0.5) * (v[0] + v[1] + v[2]);
        power += v;
        rgb.at<cv::Vec3f>(r, c) = cv::Vec3f(0, 0, 0);
      }
    lights.push_back({Normalize(centroid), power});
  }
  *probe = LatLongProbe(rgb, probe->name());
  return lights;
}

TransportOperator TransportOperator::Build(const PixelGeometry& g, const LatLongProbe& probe_in, const MerlGrid& grid,
                                           const RenderQuality& q) {
  BRDFSHOT_CHECK(q.theta_samples > 0 && q.phi_samples > 0 && q.level_step_deg > 0 && q.level_substeps > 0 &&
                 q.brdf_supersample >= 0);
  BRDFSHOT_CHECK(g.normal.size() == g.size() && g.view.size() == g.size());
  TransportOperator t;
  t.grid_ = grid;
  t.quality_ = q;
  // Suns come off the probe as given, at their exact directions, before the
  // remainder is resampled to the width the quadrature needs.
  LatLongProbe probe = probe_in;
  t.lights_ = ExtractLights(&probe, q.max_lights, q.light_share, q.light_grid_width);
  if (q.probe_width > 0 && q.probe_width < probe.width()) probe = probe.Resized(q.probe_width);
  t.probe_ = std::make_shared<const PrefilteredProbe>(probe);

  for (int a = 0; a < q.theta_samples; ++a) {
    const double u = (a + 0.5) / q.theta_samples, th = u * u * kPi / 2;
    // The cell's exact solid angle (cos θ_lo − cos θ_hi) Δφ_h: the midpoint rule
    // would be 2× off in the first cell, where dω_h ∝ u³ du and chrome lives.
    const double u0 = double(a) / q.theta_samples, u1 = double(a + 1) / q.theta_samples;
    // φ_h cells per ring: at least phi_samples (fine rings near the normal are
    // where specular peaks need them), and more towards grazing half vectors,
    // where a fixed count leaves cells ~1.6× wider than tall in ω_i (diffuse
    // bases: worst error 1.3 % → 0.9 % at 24 × 48 for +4 % samples;
    // `brdfshot bench-basis`).
    const int nphi = std::max(q.phi_samples, static_cast<int>(std::lround(4 * q.theta_samples * u)));
    const double dwh = (std::cos(u0 * u0 * kPi / 2) - std::cos(u1 * u1 * kPi / 2)) * (2 * kPi / nphi);
    for (int b = 0; b < nphi; ++b) {
      const double ph = 2 * kPi * (b + 0.5) / nphi;
      t.samples_.push_back(
          {Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)), dwh, a, b, nphi});
    }
  }

  const double step = q.level_step_deg * kPi / 180;
  t.n_levels_ = static_cast<int>(std::ceil((kPi / 2) / step)) + 1;
  const int K = q.level_substeps;
  t.sublevel_pixels_.resize((t.n_levels_ - 1) * K + 1);
  t.normal_ = g.normal;
  t.view_ = g.view;
  for (size_t p = 0; p < g.size(); ++p) {
    const double c = Dot(g.normal[p], g.view[p]);
    if (c <= 0) continue;  // facing away: the pixel stays black
    const long j = std::lround(std::acos(std::min(1.0, c)) / step * K);
    t.sublevel_pixels_[std::min<long>(j, t.sublevel_pixels_.size() - 1)].push_back(static_cast<uint32_t>(p));
  }
  // A sub-level's pixels form a ring around the view direction. In ring order,
  // neighbours see the probe near the same mirror direction, so the fine-level
  // probe texels one pixel reads are still in cache for the next (image order
  // alternates between the two sides of the ring).
  Vec3 mean_view(0, 0, 0);
  for (const Vec3& v : g.view) mean_view = mean_view + v;
  const Frame around = Frame::FromZ(Length(mean_view) > 1e-9 ? Normalize(mean_view) : Vec3(0, 0, 1));
  for (std::vector<uint32_t>& px : t.sublevel_pixels_) {
    std::vector<std::pair<double, uint32_t>> keyed;
    keyed.reserve(px.size());
    for (uint32_t p : px) {
      const double azimuth = std::atan2(Dot(g.normal[p], around.y), Dot(g.normal[p], around.x));
      keyed.push_back({std::isfinite(azimuth) ? azimuth : 0.0, p});  // NaN would break the sort's order
    }
    std::sort(keyed.begin(), keyed.end());
    for (size_t i = 0; i < px.size(); ++i) px[i] = keyed[i].second;
  }
  return t;
}

bool TransportOperator::SharesTableReadsWith(const TransportOperator& o) const {
  const RenderQuality &a = quality_, &b = o.quality_;
  return grid_ == o.grid_ && a.theta_samples == b.theta_samples && a.phi_samples == b.phi_samples &&
         a.level_step_deg == b.level_step_deg && a.level_substeps == b.level_substeps &&
         a.brdf_supersample == b.brdf_supersample;
}

template <typename RowFn>
std::vector<std::vector<std::array<MatrixXfR, 3>>> TransportOperator::ApplyImpl(
    const std::vector<const TransportOperator*>& ops, const std::vector<Eigen::Index>& widths, RowFn row) {
  BRDFSHOT_CHECK(!ops.empty() && !widths.empty());
  const TransportOperator& t0 = *ops.front();
  for (const TransportOperator* t : ops)
    BRDFSHOT_CHECK(t->SharesTableReadsWith(t0), "operators applied together must share grid and table sampling");
  const long n_ops = static_cast<long>(ops.size());
  const size_t n_parts = widths.size();
  // Part t's columns start at offset[t] of the row functor's output.
  std::vector<Eigen::Index> offset(n_parts + 1, 0);
  for (size_t t = 0; t < n_parts; ++t) offset[t + 1] = offset[t] + widths[t];
  const Eigen::Index n = offset.back();
  // Y is hundreds of MB: huge pages, and first touched by the threads in
  // parallel below (see util/huge_pages.h for what 4 KB faults cost).
  std::vector<std::vector<std::array<MatrixXfR, 3>>> Ys(ops.size(), std::vector<std::array<MatrixXfR, 3>>(n_parts));
  for (size_t o = 0; o < ops.size(); ++o)
    for (size_t t = 0; t < n_parts; ++t)
      for (auto& y : Ys[o][t]) {
        y.resize(ops[o]->pixels(), widths[t]);
        AdviseHugePages(y.data(), sizeof(float) * y.size());
      }
  const RenderQuality& quality = t0.quality_;
  const std::vector<Sample>& samples = t0.samples_;
  const int n_levels = t0.n_levels_;
  const double step = quality.level_step_deg * kPi / 180;
  const int nt = quality.theta_samples, K = quality.level_substeps;
  const Eigen::Index S_all = static_cast<Eigen::Index>(samples.size());
  // Table reads per cell: ~1 per MERL θ_h bin the cell spans (2 changed no
  // error by more than 0.1 % in bench-basis), 2 across φ_h.
  const int su = quality.brdf_supersample > 0 ? quality.brdf_supersample
                                              : std::max(1, (t0.grid_.n_th + nt - 1) / nt);
  const int sp = su > 1 ? 2 : 1;
  // Levels are processed in chunks so that only chunk + 1 matrices M live at
  // once; the last level of a chunk is the first of the next.
  constexpr int kChunk = 8;
  std::vector<MatrixXfR> M(kChunk + 1);
  const int n_sub = static_cast<int>(t0.sublevel_pixels_.size());
#pragma omp parallel
  {
    RowFn row_local = row;  // per thread: the functor may keep scratch space
    std::vector<float> tmp(n);
    std::vector<TablePoint> points;
    std::vector<int> active;
    std::vector<float> hs, dir, omega, weight, scratch, rgb;
    // Per-thread products, grown as needed: a sub-level's A, M and A·M live
    // only for one iteration, and reallocating them there costs page faults.
    std::vector<float> a_buf, m_buf, am_buf;
    for (auto& parts : Ys)
      for (auto& Y : parts)
        for (auto& y : Y) {
#pragma omp for schedule(static)
          for (Eigen::Index p = 0; p < y.rows(); ++p) y.row(p).setZero();
        }
    for (int l0 = 0; l0 < n_levels - 1; l0 += kChunk) {
      const int l1 = std::min(n_levels - 1, l0 + kChunk);  // levels l0..l1 inclusive
      const int first_new = l0 == 0 ? 0 : 1;
#pragma omp single
      {
        if (l0 > 0) std::swap(M[0], M[kChunk]);
        for (int l = first_new; l <= l1 - l0; ++l) M[l].resize(S_all, n);
      }
      // M per level: the table averaged over each sample's cell, weighted by
      // cos θ_i dω_i (weights normalised, so a cell cut by the horizon stays
      // bounded); rows of samples below the horizon are zero. M depends on
      // neither the lighting nor the pixels, so every operator shares it.
      // Sample-major: the levels of one sample read overlapping table rows
      // (θ_d moves by about a bin per level), so visiting them back to back
      // reads each row from cache rather than from the 1.7 GB table again.
      const int n_new = l1 - l0 + 1 - first_new;
#pragma omp for schedule(dynamic, 32)
      for (long r = 0; r < n_new * S_all; ++r) {
        const int l = first_new + static_cast<int>(r % n_new);
        const Sample& smp = samples[r / n_new];
        const double tl = std::min(kPi / 2, (l0 + l) * step);
        const Vec3 wo_l(std::sin(tl), 0, std::cos(tl));
        points.clear();
        double wsum = 0;
        for (int i = 0; i < su; ++i) {
          const double u = (smp.a + (i + 0.5) / su) / nt, th = u * u * kPi / 2;
          const double u0 = (smp.a + double(i) / su) / nt, u1 = (smp.a + double(i + 1) / su) / nt;
          const double dwh = std::cos(u0 * u0 * kPi / 2) - std::cos(u1 * u1 * kPi / 2);  // ∝ sub-cell dω_h
          for (int j = 0; j < sp; ++j) {
            const double ph = 2 * kPi * (smp.b + (j + 0.5) / sp) / smp.nphi;
            const Vec3 h(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
            const double cd = Dot(wo_l, h);
            if (cd <= 0) continue;
            const Vec3 wi = 2 * cd * h - wo_l;
            if (wi.z <= 0) continue;
            points.push_back({ToHalfDiff(wi, wo_l), wi.z * cd * dwh});
            wsum += points.back().weight;
          }
        }
        for (TablePoint& pt : points) pt.weight /= wsum;
        row_local(points, M[l].row(r / n_new).data());
      }
      // Sub-levels of this chunk, of every operator (the very last level
      // belongs to the last chunk).
      const int j_begin = l0 * K, j_end = l1 == n_levels - 1 ? n_sub : l1 * K;
      const long n_j = j_end - j_begin;
#pragma omp for schedule(dynamic, 1)
      for (long q = 0; q < n_ops * n_j; ++q) {
        const TransportOperator& t = *ops[q / n_j];
        std::vector<std::array<MatrixXfR, 3>>& Y = Ys[q / n_j];
        const int j = j_begin + static_cast<int>(q % n_j);
        const std::vector<uint32_t>& px = t.sublevel_pixels_[j];
        if (px.empty()) continue;
        const int l = std::min(j / K, n_levels - 2);
        const float f = static_cast<float>(j - l * K) / K;
        const MatrixXfR& Ma = M[l - l0];
        const MatrixXfR& Mb = M[l - l0 + 1];
        // Samples that can reach above the horizon for some pixel of the
        // sub-level (θ_o within a step): the rest would be all zeros.
        const double tj = std::min(kPi / 2, j * step / K);
        const Vec3 wo_j(std::sin(tj), 0, std::cos(tj));
        active.clear();
        for (int s = 0; s < S_all; ++s) {
          const Vec3& h = samples[s].h;
          const double cd = Dot(wo_j, h);
          if (cd <= 0 || 2 * cd * h.z - wo_j.z <= -2 * step) continue;
          active.push_back(s);
        }
        const Eigen::Index S = static_cast<Eigen::Index>(active.size());
        if (S == 0) continue;
        using MapR = Eigen::Map<MatrixXfR>;
        const Eigen::Index P = static_cast<Eigen::Index>(px.size());
        for (auto [buf, size] : {std::pair{&a_buf, 3 * P * S}, {&m_buf, S * n}, {&am_buf, 3 * P * n}})
          if (static_cast<Eigen::Index>(buf->size()) < size) buf->resize(size);
        MapR Mj(m_buf.data(), S, n), A(a_buf.data(), 3 * P, S), AM(am_buf.data(), 3 * P, n);
        for (Eigen::Index k = 0; k < S; ++k) Mj.row(k) = (1 - f) * Ma.row(active[k]) + f * Mb.row(active[k]);
        // Active samples as float arrays, for the vectorised loop below.
        hs.resize(4 * S);
        for (Eigen::Index k = 0; k < S; ++k) {
          const Sample& smp = samples[active[k]];
          hs[k] = static_cast<float>(smp.h.x), hs[S + k] = static_cast<float>(smp.h.y);
          hs[2 * S + k] = static_cast<float>(smp.h.z), hs[3 * S + k] = static_cast<float>(4 * smp.dwh);
        }
        const float *hx = hs.data(), *hy = hx + S, *hz = hy + S, *dw4 = hz + S;
        dir.resize(3 * S), omega.resize(S), weight.resize(S), scratch.resize(3 * S), rgb.resize(3 * S);
        // A: each pixel's lighting per sample, channel-major rows.
        for (Eigen::Index i = 0; i < P; ++i) {
          const size_t p = px[i];
          const Frame fr = Frame::FromZX(t.normal_[p], t.view_[p]);
          const Vec3 wo_d = fr.ToLocal(t.view_[p]);
          const float wox = static_cast<float>(wo_d.x), woy = static_cast<float>(wo_d.y),
                      woz = static_cast<float>(wo_d.z);
          float F[9];  // local → probe frame, row-major
          for (int r = 0; r < 3; ++r)
            F[3 * r] = static_cast<float>(fr.x[r]), F[3 * r + 1] = static_cast<float>(fr.y[r]),
                  F[3 * r + 2] = static_cast<float>(fr.z[r]);
          for (Eigen::Index k = 0; k < S; ++k) {  // vectorised
            const float cd = wox * hx[k] + woy * hy[k] + woz * hz[k];
            const float wx = 2 * cd * hx[k] - wox, wy = 2 * cd * hy[k] - woy, wz = 2 * cd * hz[k] - woz;
            const bool ok = cd > 0 && wz > 0;
            dir[3 * k] = F[0] * wx + F[1] * wy + F[2] * wz;
            dir[3 * k + 1] = F[3] * wx + F[4] * wy + F[5] * wz;
            dir[3 * k + 2] = F[6] * wx + F[7] * wy + F[8] * wz;
            omega[k] = ok ? cd * dw4[k] : 0.0f;  // dω_i = 4 (ω_o·h) dω_h
            weight[k] = ok ? wz * omega[k] : 0.0f;
          }
          t.probe_->LookupMany(static_cast<int>(S), dir.data(), omega.data(), scratch.data(), rgb.data());
          for (int c = 0; c < 3; ++c) {
            float* a_row = A.row(c * P + i).data();
            for (Eigen::Index k = 0; k < S; ++k) a_row[k] = weight[k] * rgb[3 * k + c];
          }
        }
        AM.noalias() = A * Mj;
        for (size_t part = 0; part < n_parts; ++part)
          for (Eigen::Index i = 0; i < P; ++i)
            for (int c = 0; c < 3; ++c)
              Y[part][c].row(px[i]) = AM.row(c * P + i).segment(offset[part], widths[part]);
      }
    }
    // Suns: exact per pixel, the table read at the pixel's own (ω_i, ω_o).
    for (long o = 0; o < n_ops; ++o) {
      const TransportOperator& t = *ops[o];
      if (t.lights_.empty()) continue;
      std::vector<std::array<MatrixXfR, 3>>& Y = Ys[o];
#pragma omp for schedule(dynamic, 16)
      for (long p = 0; p < static_cast<long>(t.pixels()); ++p) {
        const Frame f = Frame::FromZX(t.normal_[p], t.view_[p]);
        const Vec3 wo = f.ToLocal(t.view_[p]);
        if (wo.z <= 0) continue;
        for (const DirectionalLight& l : t.lights_) {
          const Vec3 wi = f.ToLocal(l.direction);
          if (wi.z <= 0) continue;
          points.assign(1, TablePoint{ToHalfDiff(wi, wo), 1.0});
          row_local(points, tmp.data());
          for (int c = 0; c < 3; ++c) {
            const float w = static_cast<float>(wi.z * l.power[c]);
            for (size_t part = 0; part < n_parts; ++part) {
              float* y = Y[part][c].row(p).data();
              const float* v = tmp.data() + offset[part];
              for (Eigen::Index j = 0; j < widths[part]; ++j) y[j] += w * v[j];
            }
          }
        }
      }
    }
  }
  return Ys;
}

std::array<MatrixXfR, 3> TransportOperator::Apply(const TablesRef& B) const {
  return std::move(ApplyAll({this}, {MapOf(B)}).front().front());
}

std::vector<std::array<MatrixXfR, 3>> TransportOperator::ApplyToEach(const std::vector<const TransportOperator*>& ops,
                                                                      const TablesRef& B) {
  std::vector<std::array<MatrixXfR, 3>> Ys;
  for (auto& parts : ApplyAll(ops, {MapOf(B)})) Ys.push_back(std::move(parts.front()));
  return Ys;
}

std::vector<std::vector<std::array<MatrixXfR, 3>>> TransportOperator::ApplyAll(
    const std::vector<const TransportOperator*>& ops, const std::vector<TablesMap>& tables) {
  BRDFSHOT_CHECK(!ops.empty() && !tables.empty());
  const MerlGrid& grid = ops.front()->grid_;
  std::vector<Eigen::Index> widths;
  for (const TablesMap& B : tables) {
    BRDFSHOT_CHECK(static_cast<size_t>(B.rows()) == grid.size(),
                   "basis matrix has " << B.rows() << " rows, operator expects " << grid.size());
    widths.push_back(B.cols());
  }
  struct Corner {
    size_t idx;
    double w;
  };
  return ApplyImpl(ops, widths, [&, corners = std::vector<Corner>()](const std::vector<TablePoint>& pts, float* out) mutable {
    // Gather every point's trilinear corners, merge repeated entries, then read
    // each table's row once.
    corners.clear();
    for (const TablePoint& pt : pts) {
      size_t idx[8];
      double w[8];
      const int k = grid.TrilinearCorners(pt.hd, idx, w);
      for (int a = 0; a < k; ++a) corners.push_back({idx[a], w[a] * pt.weight});
    }
    std::sort(corners.begin(), corners.end(), [](const Corner& x, const Corner& y) { return x.idx < y.idx; });
    size_t unique = 0;
    for (size_t a = 0; a < corners.size();) {
      const size_t idx = corners[a].idx;
      double w = 0;
      for (; a < corners.size() && corners[a].idx == idx; ++a) w += corners[a].w;
      corners[unique++] = {idx, w};
    }
    float* part_out = out;
    for (const TablesMap& B : tables) {
      const Eigen::Index n = B.cols();
      std::fill(part_out, part_out + n, 0.0f);
      for (size_t a = 0; a < unique; ++a) {
        const float wf = static_cast<float>(corners[a].w);
        const float* b = B.row(static_cast<Eigen::Index>(corners[a].idx)).data();
        for (Eigen::Index j = 0; j < n; ++j) part_out[j] += wf * b[j];
      }
      part_out += n;
    }
  });
}

Eigen::MatrixXd TransportOperator::Render(const MerlBrdf& brdf) const { return RenderAll({&brdf}).front(); }

std::vector<Eigen::MatrixXd> TransportOperator::RenderAll(const std::vector<const MerlBrdf*>& brdfs) const {
  for (const MerlBrdf* b : brdfs) BRDFSHOT_CHECK(b && b->grid() == grid_, "BRDF grid differs from the operator's grid");
  const size_t count = brdfs.size();
  const auto Y = ApplyImpl({this}, std::vector<Eigen::Index>(count, 3),
                           [&, acc = std::vector<double>(3 * count)](const std::vector<TablePoint>& pts,
                                                                     float* out) mutable {
                             // Unmeasured entries read as 0, exactly as the basis matrix
                             // stores them, so rendering a table and applying the operator
                             // to its columns agree.
                             std::fill(acc.begin(), acc.end(), 0.0);
                             for (const TablePoint& pt : pts) {
                               size_t idx[8];
                               double w[8];
                               const int k = grid_.TrilinearCorners(pt.hd, idx, w);
                               for (int a = 0; a < k; ++a)
                                 for (size_t t = 0; t < count; ++t)
                                   for (int c = 0; c < 3; ++c)
                                     acc[3 * t + static_cast<size_t>(c)] +=
                                         pt.weight * w[a] * std::max(0.0, brdfs[t]->Value(c, idx[a]));
                             }
                             for (size_t i = 0; i < 3 * count; ++i) out[i] = static_cast<float>(acc[i]);
                           })
                     .front();
  std::vector<Eigen::MatrixXd> images;
  for (size_t t = 0; t < count; ++t) {
    Eigen::MatrixXd y(pixels(), 3);
    for (int c = 0; c < 3; ++c) y.col(c) = Y[t][c].col(c).cast<double>();
    images.push_back(std::move(y));
  }
  return images;
}

}  // namespace brdfshot
