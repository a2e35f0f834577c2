#include "viaduct/ident/oma.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "viaduct/core/eigensolvers.hpp"
#include <Eigen/QR>
#include <Eigen/SVD>

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"
#include "viaduct/ident/modal_fit.hpp"
#include "viaduct/signal/peaks.hpp"
#include "viaduct/signal/resample.hpp"

namespace viaduct::ident {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string channel_name(const std::vector<std::string>& names, Index c) {
  return static_cast<std::size_t>(c) < names.size() ? "channel '" + names[static_cast<std::size_t>(c)] + "'"
                                                    : "channel " + std::to_string(c + 1);
}

double mac_of(const ComplexVector& a, const ComplexVector& b) {
  if (a.size() == 0 || a.size() != b.size()) return 1.0;  // nothing to compare: frequency decides
  const double den = a.squaredNorm() * b.squaredNorm();
  return den > 0.0 ? std::norm(a.dot(b)) / den : 0.0;
}

Index next_pow2(Index n) {
  Index p = 1;
  while (p < n) p *= 2;
  return p;
}

// Block Toeplitz matrix of lags 1..2i-1: block (p, q) = R_{i+p-q}.
Matrix toeplitz(const std::vector<Matrix>& lag, Index i) {
  const Index l = lag[0].rows(), r = lag[0].cols();
  Matrix t(l * i, r * i);
  for (Index p = 0; p < i; ++p)
    for (Index q = 0; q < i; ++q) t.block(p * l, q * r, l, r) = lag[static_cast<std::size_t>(i + p - q)];
  return t;
}

// U_n S_n^{1/2} of the Toeplitz matrix for the largest order.
Matrix observability(const Matrix& t, int max_order, Vector* singular_values) {
  Eigen::BDCSVD<Matrix> svd(t, Eigen::ComputeThinU);
  if (singular_values) *singular_values = svd.singularValues();
  const Index n = std::min<Index>(max_order, svd.singularValues().size());
  return svd.matrixU().leftCols(n) * svd.singularValues().head(n).cwiseSqrt().asDiagonal();
}

double median_of(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m), v.end());
  double med = v[m];
  if (v.size() % 2 == 0) med = 0.5 * (med + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m)));
  return med;
}

double std_of(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  double s = 0.0;
  for (double x : v) s += (x - mean) * (x - mean);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

// Jackknife standard deviation sqrt((J-1)/J Σ (θ_j - θ̄)²).
double jackknife_std(const std::vector<double>& v) {
  if (v.size() < 3) return std::numeric_limits<double>::quiet_NaN();
  const double n = static_cast<double>(v.size());
  const double mean = std::accumulate(v.begin(), v.end(), 0.0) / n;
  double s = 0.0;
  for (double x : v) s += (x - mean) * (x - mean);
  return std::sqrt((n - 1.0) / n * s);
}

struct UnionFind {
  std::vector<std::size_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), std::size_t{0}); }
  std::size_t find(std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void join(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};

// Poles stable in frequency and shape (indices into poles) joined by single linkage on |Δf|/f + 1 − MAC.
std::vector<std::vector<std::size_t>> link_stable_poles(const std::vector<SsiPole>& poles, double max_distance) {
  std::vector<std::size_t> stable;
  for (std::size_t k = 0; k < poles.size(); ++k)
    if (poles[k].clusterable()) stable.push_back(k);
  std::sort(stable.begin(), stable.end(), [&](std::size_t a, std::size_t b) { return poles[a].frequency_hz < poles[b].frequency_hz; });
  UnionFind uf(stable.size());
  for (std::size_t a = 0; a < stable.size(); ++a)
    for (std::size_t b = a + 1; b < stable.size(); ++b) {
      const SsiPole& pa = poles[stable[a]];
      const SsiPole& pb = poles[stable[b]];
      const double df = (pb.frequency_hz - pa.frequency_hz) / pb.frequency_hz;
      if (df >= max_distance) break;
      if (pa.order == pb.order) continue;  // two poles of one model are two modes
      if (df + 1.0 - mac_of(pa.shape, pb.shape) < max_distance) uf.join(a, b);
    }
  std::vector<std::vector<std::size_t>> groups(stable.size());
  for (std::size_t a = 0; a < stable.size(); ++a) groups[uf.find(a)].push_back(stable[a]);
  groups.erase(std::remove_if(groups.begin(), groups.end(), [](const auto& g) { return g.empty(); }), groups.end());
  return groups;
}

// A cluster holding k poles of most of its orders is k modes (close modes whose shapes the
// noise made alike): its poles of such orders, by frequency, seed k groups; the others join
// the group of the nearest frequency.
std::vector<std::vector<std::size_t>> split_cluster(const std::vector<SsiPole>& poles, const std::vector<std::size_t>& cluster) {
  std::map<int, std::vector<std::size_t>> by_order;
  for (std::size_t k : cluster) by_order[poles[k].order].push_back(k);
  std::vector<std::size_t> counts;
  for (const auto& [order, ks] : by_order) counts.push_back(ks.size());
  std::sort(counts.begin(), counts.end());
  const std::size_t k = counts[counts.size() / 2];
  if (k < 2) return {cluster};
  std::vector<std::vector<double>> seed(k);
  for (auto& [order, ks] : by_order) {
    if (ks.size() != k) continue;
    std::sort(ks.begin(), ks.end(), [&](std::size_t a, std::size_t b) { return poles[a].frequency_hz < poles[b].frequency_hz; });
    for (std::size_t g = 0; g < k; ++g) seed[g].push_back(poles[ks[g]].frequency_hz);
  }
  std::vector<double> centre(k);
  for (std::size_t g = 0; g < k; ++g) centre[g] = median_of(seed[g]);
  std::vector<std::vector<std::size_t>> out(k);
  for (std::size_t p : cluster) {
    std::size_t best = 0;
    for (std::size_t g = 1; g < k; ++g)
      if (std::abs(poles[p].frequency_hz - centre[g]) < std::abs(poles[p].frequency_hz - centre[best])) best = g;
    out[best].push_back(p);
  }
  return out;
}

// At most one pole per order (the one nearest the group's median frequency).
std::vector<std::size_t> one_per_order(const std::vector<SsiPole>& poles, const std::vector<std::size_t>& group) {
  std::vector<double> f;
  for (std::size_t k : group) f.push_back(poles[k].frequency_hz);
  const double med = median_of(f);
  std::map<int, std::size_t> best;
  for (std::size_t k : group) {
    auto it = best.find(poles[k].order);
    if (it == best.end() || std::abs(poles[k].frequency_hz - med) < std::abs(poles[it->second].frequency_hz - med)) best[poles[k].order] = k;
  }
  std::vector<std::size_t> out;
  for (const auto& [order, k] : best) out.push_back(k);
  return out;
}

OmaMode mode_of_cluster(const std::vector<SsiPole>& poles, const std::vector<std::size_t>& members) {
  std::vector<double> f, z;
  for (std::size_t k : members) {
    f.push_back(poles[k].frequency_hz);
    z.push_back(poles[k].damping_ratio);
  }
  const double med = median_of(f);
  std::size_t rep = members.front();
  for (std::size_t k : members) {
    const double d = std::abs(poles[k].frequency_hz - med), d_rep = std::abs(poles[rep].frequency_hz - med);
    if (d < d_rep || (d == d_rep && poles[k].order > poles[rep].order)) rep = k;
  }
  OmaMode m;
  m.frequency_hz = med;
  m.damping_ratio = median_of(z);
  for (std::size_t k : members) m.orders.push_back(poles[k].order);
  m.frequency_spread_hz = std_of(f);
  m.damping_spread = std_of(z);
  m.shape = poles[rep].shape;
  m.mpc = poles[rep].mpc;
  m.mpd_deg = poles[rep].mpd_deg;
  m.order = poles[rep].order;
  m.n_poles = static_cast<Index>(members.size());
  return m;
}

// Marks each pole physical and stable against the previous order's poles.
void stabilize(std::vector<SsiPole>& poles, std::size_t begin_prev, std::size_t begin, const SsiOptions& o, double f_lo, double f_hi) {
  for (std::size_t k = begin; k < poles.size(); ++k) {
    SsiPole& p = poles[k];
    p.physical = p.frequency_hz >= f_lo && p.frequency_hz <= f_hi && p.damping_ratio > 0.0 && p.damping_ratio <= o.max_damping &&
                 p.mpc >= o.min_mpc && p.mpd_deg <= o.max_mpd_deg;
    std::size_t near = begin;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t q = begin_prev; q < begin; ++q) {
      const double d = std::abs(poles[q].frequency_hz - p.frequency_hz);
      if (d < best) {
        best = d;
        near = q;
      }
    }
    if (near == begin) continue;  // the first order, or none before
    const SsiPole& q = poles[near];
    p.stable_frequency = best / p.frequency_hz < o.tol_frequency;
    p.stable_damping = q.damping_ratio > 0.0 && std::abs(p.damping_ratio - q.damping_ratio) / q.damping_ratio < o.tol_damping;
    p.stable_shape = mac_of(p.shape, q.shape) > o.tol_mac;
  }
}

Index auto_block_rows(const SsiOptions& o, Index n_refs, double fs_hz) {
  const double f_low = o.f_min_hz > 0.0 ? o.f_min_hz : fs_hz / 100.0;
  const Index by_order = (o.max_order + n_refs - 1) / n_refs + 1;
  const Index by_frequency = static_cast<Index>(std::ceil(fs_hz / (2.0 * f_low)));
  return std::max(by_order, std::min(by_frequency, std::max<Index>(1200 / n_refs, by_order)));
}

}  // namespace

void check_oma_record(const Matrix& y, double fs_hz, const std::vector<std::string>& names, Index min_channels, double f_low_hz,
                      double f_high_hz, double min_periods) {
  if (!(fs_hz > 0.0) || !std::isfinite(fs_hz)) throw InputError("the sampling rate must be > 0 (" + format_number(fs_hz) + " Hz)");
  if (y.cols() < min_channels)
    throw InputError("output-only identification by SSI needs at least " + std::to_string(min_channels) + " channels; the record has " +
                     std::to_string(y.cols()) + " (give more with --channel)");
  const double nyquist = 0.5 * fs_hz;
  if (f_low_hz >= nyquist)
    throw InputError("the band starts at " + format_number(f_low_hz) + " Hz, at or above the Nyquist frequency " + format_number(nyquist) +
                     " Hz of the record (" + format_number(fs_hz) + " Hz)");
  if (std::isfinite(f_high_hz) && f_high_hz > nyquist)
    throw InputError("the band ends at " + format_number(f_high_hz) + " Hz, above the Nyquist frequency " + format_number(nyquist) +
                     " Hz of the record (" + format_number(fs_hz) + " Hz)");
  const Index n = y.rows();
  if (n < 64) throw InputError("the record is too short for output-only identification (" + std::to_string(n) + " samples)");
  const double duration = static_cast<double>(n) / fs_hz;
  if (f_low_hz > 0.0 && duration * f_low_hz < min_periods)
    throw InputError("the record (" + format_number(duration, 4) + " s) holds " + format_number(duration * f_low_hz, 3) +
                     " periods of the band's lowest frequency " + format_number(f_low_hz) + " Hz; at least " + format_number(min_periods) +
                     " are needed (a longer record, or a higher --f-min-hz)");
  for (Index c = 0; c < y.cols(); ++c) {
    const auto col = y.col(c);
    if (!col.allFinite()) throw InputError(channel_name(names, c) + " holds NaN or infinite samples (a gap: cut the record or fill it)");
    const double hi = col.maxCoeff(), lo = col.minCoeff();
    if (!(hi > lo)) throw InputError(channel_name(names, c) + " is constant (" + format_number(hi) + "): a dead or disconnected sensor");
    const Index at_hi = (col.array() == hi).count(), at_lo = (col.array() == lo).count();
    const Index limit = std::max<Index>(3, n / 100);
    if (at_hi >= limit || at_lo >= limit)
      throw InputError(channel_name(names, c) + " is clipped: " + std::to_string(std::max(at_hi, at_lo)) + " of " + std::to_string(n) +
                       " samples sit at its extreme value " + format_number(at_hi >= limit ? hi : lo) +
                       " (the logger's range was exceeded; leave the channel out)");
  }
}

std::string stationarity_warning(const Matrix& y, double fs_hz, double t0_s) {
  constexpr Index kPieces = 10;
  const Index n = y.rows(), len = n / kPieces;
  if (len < 64 || y.cols() < 1) return "";
  Vector level = Vector::Zero(kPieces);
  Index used = 0;
  for (Index c = 0; c < y.cols(); ++c) {
    const Vector x = y.col(c).array() - y.col(c).mean();
    const double whole = std::sqrt(x.squaredNorm() / static_cast<double>(n));
    if (!(whole > 0.0)) continue;
    ++used;
    for (Index k = 0; k < kPieces; ++k) {  // about the piece's own mean: a deflection's quasi-static shift is no burst
      const auto piece = x.segment(k * len, len);
      level[k] += (piece.array() - piece.mean()).square().sum() / static_cast<double>(len) / (whole * whole);
    }
  }
  if (used == 0) return "";
  level = (level / static_cast<double>(used)).cwiseSqrt();
  Index loud = 0, quiet = 0;
  const double hi = level.maxCoeff(&loud), lo = level.minCoeff(&quiet);
  if (!(hi > kMaxStationaryRmsRatio * lo)) return "";
  auto span = [&](Index k) {
    return format_number(t0_s + static_cast<double>(k * len) / fs_hz, 4) + " to " +
           format_number(t0_s + static_cast<double>((k + 1) * len) / fs_hz, 4) + " s";
  };
  return "not stationary: its loudest tenth (" + span(loud) + ") has " + (lo > 0.0 ? format_number(hi / lo, 3) : std::string("infinitely many")) +
         " times the RMS of its quietest (" + span(quiet) + "), a train passage or another burst. SSI-COV and FDD assume "
         "ambient (stationary, broadband) excitation: a passage's forced response, the axles' passing frequency and its "
         "harmonics, can pass as modes. Cut the burst out (--start-s, --end-s, --window-s), or identify the free decay after a "
         "passage (--free-decay)";
}

bool SsiOptions::is_valid(Index n_channels, double fs_hz, std::string* why) const {
  OptionsCheck c("SsiOptions", why);
  bool refs_ok = true;
  for (Index r : references) refs_ok = refs_ok && r >= 0 && r < n_channels;
  if (!refs_ok) return c.fail("references", "(a channel)", "every reference is one of the record's " + std::to_string(n_channels) + " channels");
  return c.require(f_min_hz >= 0.0, "f_min_hz", f_min_hz, "f_min_hz >= 0") &&
         c.require_or_infinite(f_max_hz > f_min_hz, "f_max_hz", f_max_hz, "f_max_hz > f_min_hz") &&
         c.require(f_min_hz < 0.5 * fs_hz, "f_min_hz", f_min_hz, "f_min_hz below the Nyquist frequency " + format_number(0.5 * fs_hz) + " Hz") &&
         c.require(block_rows >= 0, "block_rows", static_cast<double>(block_rows), "block_rows >= 0 (0: chosen)") &&
         c.require(min_order >= 2 && min_order % 2 == 0, "min_order", min_order, "min_order even, >= 2") &&
         c.require(max_order >= min_order && max_order <= 400 && max_order % 2 == 0, "max_order", max_order,
                   "max_order even, in [min_order, 400]") &&
         c.require(order_step >= 2 && order_step % 2 == 0, "order_step", order_step, "order_step even, >= 2") &&
         c.require(tol_frequency > 0.0, "tol_frequency", tol_frequency, "tol_frequency > 0") &&
         c.require(tol_damping > 0.0, "tol_damping", tol_damping, "tol_damping > 0") &&
         c.require(tol_mac >= 0.0 && tol_mac < 1.0, "tol_mac", tol_mac, "tol_mac in [0, 1)") &&
         c.require(max_damping > 0.0 && max_damping < 1.0, "max_damping", max_damping, "max_damping in (0, 1)") &&
         c.require(min_mpc >= 0.0 && min_mpc <= 1.0, "min_mpc", min_mpc, "min_mpc in [0, 1]") &&
         c.require(max_mpd_deg > 0.0 && max_mpd_deg <= 90.0, "max_mpd_deg", max_mpd_deg, "max_mpd_deg in (0, 90]") &&
         c.require(cluster_distance > 0.0, "cluster_distance", cluster_distance, "cluster_distance > 0") &&
         c.require(min_cluster_fraction > 0.0 && min_cluster_fraction <= 1.0, "min_cluster_fraction", min_cluster_fraction,
                   "min_cluster_fraction in (0, 1]") &&
         c.require(uncertainty_blocks == 0 || uncertainty_blocks >= 4, "uncertainty_blocks", static_cast<double>(uncertainty_blocks),
                   "uncertainty_blocks 0 (none) or >= 4");
}

Correlations output_correlations(const Matrix& y0, const std::vector<Index>& refs, Index n_lags, Index blocks, bool unbiased) {
  const Index n = y0.rows(), l = y0.cols(), r = static_cast<Index>(refs.size());
  blocks = std::max<Index>(1, blocks);
  const Index piece = n / blocks;
  if (piece <= n_lags)
    throw InputError("the record (" + std::to_string(n) + " samples) is too short for " + std::to_string(n_lags) + " lags in each of " +
                     std::to_string(blocks) + " pieces (fewer jackknife blocks, fewer block rows, or a longer record)");
  const Eigen::RowVectorXd mean = y0.colwise().mean();  // removed piece by piece: no copy of the record
  Correlations c;
  c.unbiased = unbiased;
  for (Index b = 0; b < blocks; ++b) {
    const Index start = b * piece, len = b + 1 == blocks ? n - start : piece;
    const Index nfft = next_pow2(len + n_lags);
    std::vector<ComplexVector> spectra(static_cast<std::size_t>(l));
    for (Index a = 0; a < l; ++a) {
      Vector padded = Vector::Zero(nfft);
      padded.head(len) = y0.col(a).segment(start, len).array() - mean[a];
      spectra[static_cast<std::size_t>(a)] = signal::rfft(padded);
    }
    std::vector<Matrix> sums(static_cast<std::size_t>(n_lags), Matrix(l, r));
    for (Index a = 0; a < l; ++a)
      for (Index j = 0; j < r; ++j) {
        const ComplexVector prod = spectra[static_cast<std::size_t>(a)].cwiseProduct(spectra[static_cast<std::size_t>(refs[static_cast<std::size_t>(j)])].conjugate());
        const Vector xc = signal::irfft(prod, nfft);
        for (Index k = 0; k < n_lags; ++k) sums[static_cast<std::size_t>(k)](a, j) = xc[k];
      }
    Vector count(n_lags);
    for (Index k = 0; k < n_lags; ++k) count[k] = static_cast<double>(len - k);
    c.block.push_back(std::move(sums));
    c.block_count.push_back(count);
  }
  c.lag.assign(static_cast<std::size_t>(n_lags), Matrix::Zero(l, r));
  for (Index k = 0; k < n_lags; ++k) {
    double count = 0.0;
    for (std::size_t b = 0; b < c.block.size(); ++b) {
      c.lag[static_cast<std::size_t>(k)] += c.block[b][static_cast<std::size_t>(k)];
      count += c.block_count[b][k];
    }
    if (unbiased) c.lag[static_cast<std::size_t>(k)] /= count;
  }
  return c;
}

const char* pole_status(const SsiPole& p) {
  if (!p.physical) return "spurious";
  if (p.stable()) return "stable";
  if (p.stable_frequency && p.stable_shape) return "shape";
  if (p.stable_frequency && p.stable_damping) return "damping";
  if (p.stable_frequency) return "frequency";
  return "new";
}

ShapeQuality shape_quality(const ComplexVector& phi) {
  ShapeQuality q;
  const Vector re = phi.real(), im = phi.imag();
  const double sxx = re.squaredNorm(), syy = im.squaredNorm(), sxy = re.dot(im);
  const double half = 0.5 * (sxx - syy), root = std::sqrt(half * half + sxy * sxy), mean = 0.5 * (sxx + syy);
  const double l1 = mean + root, l2 = mean - root;
  q.mpc = l1 + l2 > 0.0 ? std::pow((l1 - l2) / (l1 + l2), 2) : 0.0;
  const double theta = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
  ComplexVector rotated = phi * std::polar(1.0, -theta);
  double wsum = 0.0, dsum = 0.0;
  Index big = 0;
  for (Index j = 0; j < rotated.size(); ++j) {
    const double a = std::abs(rotated[j]);
    wsum += a;
    dsum += a * std::atan2(std::abs(rotated[j].imag()), std::abs(rotated[j].real()));
    if (a > std::abs(rotated[big])) big = j;
  }
  q.mpd_deg = wsum > 0.0 ? dsum / wsum * 180.0 / kPi : 0.0;
  const double scale = std::abs(rotated[big]) * (rotated[big].real() < 0.0 ? -1.0 : 1.0);
  q.normalised = scale != 0.0 ? ComplexVector(rotated / scale) : rotated;
  return q;
}

std::vector<SsiPole> ssi_poles(const Matrix& us_sqrt, Index n_channels, int order, double fs_hz) {
  const Matrix o = us_sqrt.leftCols(order);
  const Index rows = o.rows() - n_channels;
  const Matrix a = o.topRows(rows).colPivHouseholderQr().solve(o.bottomRows(rows));
  const Matrix c = o.topRows(n_channels);
  Eigen::EigenSolver<Matrix> es(a, true);
  std::vector<SsiPole> poles;
  for (Index k = 0; k < a.rows(); ++k) {
    const std::complex<double> mu = es.eigenvalues()[k];
    if (!(mu.imag() > 0.0)) continue;  // one of each conjugate pair; real poles do not oscillate
    const std::complex<double> lambda = std::log(mu) * fs_hz;
    SsiPole p;
    p.order = order;
    p.frequency_hz = std::abs(lambda) / (2.0 * kPi);
    p.damping_ratio = -lambda.real() / std::abs(lambda);
    const ShapeQuality q = shape_quality(c.cast<std::complex<double>>() * es.eigenvectors().col(k));
    p.mpc = q.mpc;
    p.mpd_deg = q.mpd_deg;
    p.shape = q.normalised;
    poles.push_back(std::move(p));
  }
  std::sort(poles.begin(), poles.end(), [](const SsiPole& x, const SsiPole& y) { return x.frequency_hz < y.frequency_hz; });
  return poles;
}

namespace {

// f and ζ of each mode from the Toeplitz matrix without one piece of the record, each piece in
// turn: the medians over the mode's orders of the poles nearest to it (as the mode is the
// median of its cluster); their jackknife standard deviations.
void jackknife(const Correlations& c, Index i, Index n_channels, double fs_hz, std::vector<OmaMode>& modes) {
  const std::size_t blocks = c.block.size();
  std::vector<std::vector<double>> f(modes.size()), z(modes.size());
  int top = 0;
  for (const auto& m : modes)
    for (int order : m.orders) top = std::max(top, order);
  for (std::size_t left = 0; left < blocks; ++left) {
    std::vector<Matrix> lag(c.lag.size());
    for (std::size_t k = 0; k < lag.size(); ++k) {
      Matrix s = Matrix::Zero(c.lag[k].rows(), c.lag[k].cols());
      double count = 0.0;
      for (std::size_t b = 0; b < blocks; ++b) {
        if (b == left) continue;
        s += c.block[b][k];
        count += c.block_count[b][static_cast<Index>(k)];
      }
      lag[k] = c.unbiased ? Matrix(s / count) : s;
    }
    const Matrix us = observability(toeplitz(lag, i), top, nullptr);
    std::map<int, std::vector<SsiPole>> by_order;
    for (std::size_t m = 0; m < modes.size(); ++m) {
      std::vector<double> fm, zm;
      for (int order : modes[m].orders) {
        if (!by_order.count(order)) by_order[order] = ssi_poles(us, n_channels, order, fs_hz);
        const SsiPole* best = nullptr;
        double best_d = 0.05;  // a replicate's pole further than this is not the mode
        for (const SsiPole& p : by_order[order]) {
          const double d = std::abs(p.frequency_hz - modes[m].frequency_hz) / modes[m].frequency_hz + 1.0 - mac_of(p.shape, modes[m].shape);
          if (d < best_d) {
            best_d = d;
            best = &p;
          }
        }
        if (!best) continue;
        fm.push_back(best->frequency_hz);
        zm.push_back(best->damping_ratio);
      }
      if (2 * fm.size() < modes[m].orders.size()) continue;  // lost in this replicate
      f[m].push_back(median_of(fm));
      z[m].push_back(median_of(zm));
    }
  }
  for (std::size_t m = 0; m < modes.size(); ++m) {
    // A mode some replicates lose is not estimated stably: no standard deviation, and a note.
    if (f[m].size() + 1 < blocks) {
      modes[m].note += std::string(modes[m].note.empty() ? "" : "; ") + "found in " + std::to_string(f[m].size()) + " of " +
                       std::to_string(blocks) + " jackknife replicates (no standard deviation)";
      continue;
    }
    modes[m].frequency_std_hz = jackknife_std(f[m]);
    modes[m].damping_std = jackknife_std(z[m]);
  }
}

}  // namespace

SsiResult ssi_cov(const Matrix& y, double fs_hz, const SsiOptions& o) {
  std::string why;
  if (!o.is_valid(y.cols(), fs_hz, &why)) throw InputError("SSI-COV: " + why);
  check_oma_record(y, fs_hz, {}, 2, 0.0, std::numeric_limits<double>::infinity(), 0.0);
  std::vector<Index> refs = o.references;
  if (refs.empty())
    for (Index c = 0; c < y.cols(); ++c) refs.push_back(c);
  SsiResult r;
  r.f_min_hz = o.f_min_hz;
  r.f_max_hz = std::min(o.f_max_hz, 0.99 * 0.5 * fs_hz);
  const Index l = y.cols(), nr = static_cast<Index>(refs.size());
  const Index i = o.block_rows > 0 ? o.block_rows : auto_block_rows(o, nr, fs_hz);
  r.block_rows = i;
  if (o.max_order > nr * i || o.max_order > l * (i - 1))
    throw InputError("SSI-COV: max_order " + std::to_string(o.max_order) + " exceeds what " + std::to_string(i) + " block rows of " +
                     std::to_string(l) + " channels and " + std::to_string(nr) + " references give (" +
                     std::to_string(std::min(nr * i, l * (i - 1))) + "): more block rows, or a lower order");
  const Index blocks = o.free_decay ? 1 : std::max<Index>(1, o.uncertainty_blocks);
  const Correlations c = output_correlations(y, refs, 2 * i, blocks, !o.free_decay);
  const Matrix us = observability(toeplitz(c.lag, i), o.max_order, &r.singular_values);
  std::size_t begin_prev = 0;
  for (int n = o.min_order; n <= o.max_order; n += o.order_step) {
    if (n > us.cols()) break;
    const std::size_t begin = r.poles.size();
    for (SsiPole& p : ssi_poles(us, l, n, fs_hz)) r.poles.push_back(std::move(p));
    stabilize(r.poles, begin_prev, begin, o, r.f_min_hz, r.f_max_hz);
    begin_prev = begin;
    r.orders.push_back(n);
  }
  const double needed = std::max(2.0, o.min_cluster_fraction * static_cast<double>(r.orders.size()));
  std::vector<std::vector<std::size_t>> members;
  for (const auto& cluster : link_stable_poles(r.poles, o.cluster_distance))
    for (const auto& group : split_cluster(r.poles, cluster)) {
      const std::vector<std::size_t> kept = one_per_order(r.poles, group);
      if (static_cast<double>(kept.size()) >= needed) members.push_back(kept);
    }
  for (const auto& kept : members) r.modes.push_back(mode_of_cluster(r.poles, kept));
  std::vector<std::size_t> order(r.modes.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return r.modes[a].frequency_hz < r.modes[b].frequency_hz; });
  std::vector<OmaMode> sorted;
  for (std::size_t m = 0; m < order.size(); ++m) {
    sorted.push_back(r.modes[order[m]]);
    for (std::size_t k : members[order[m]]) r.poles[k].cluster = static_cast<int>(m);
  }
  r.modes = std::move(sorted);
  const double duration = static_cast<double>(y.rows()) / fs_hz;
  for (OmaMode& m : r.modes) {
    const double edge = 0.02 * m.frequency_hz;
    if ((o.f_min_hz > 0.0 && m.frequency_hz - o.f_min_hz < edge) || r.f_max_hz - m.frequency_hz < edge)
      m.note = "at the band's edge (within 2 %): a mode outside may be cut, widen the band";
    if (m.mpc < 0.5)
      m.note += std::string(m.note.empty() ? "" : "; ") + "complex shape (MPC " + format_number(m.mpc, 2) +
                "): closely spaced modes the record does not separate, or non-proportional damping";
    if (!o.free_decay && duration * m.frequency_hz < 200.0)
      m.note += std::string(m.note.empty() ? "" : "; ") + "only " + format_number(duration * m.frequency_hz, 3) +
                " periods in the record (200 or more advised)";
  }
  // A mode close to a better-supported one with a similar shape may be that mode split by the
  // clustering (its poles wander between orders): said where the user reads it, not dropped, as
  // two real modes can be that close.
  for (std::size_t a = 0; a < r.modes.size(); ++a)
    for (std::size_t b = 0; b < r.modes.size(); ++b) {
      const OmaMode &ma = r.modes[a], &mb = r.modes[b];
      const double mac = mac_of(ma.shape, mb.shape);
      if (a == b || mb.n_poles <= ma.n_poles || std::abs(ma.frequency_hz - mb.frequency_hz) > 0.03 * mb.frequency_hz || mac < 0.9) continue;
      r.modes[a].note += std::string(ma.note.empty() ? "" : "; ") + "beside the mode at " + format_number(mb.frequency_hz, 4) +
                         " Hz with more poles and a similar shape (MAC " + format_number(mac, 2) + "): perhaps that mode split";
      break;
    }
  if (blocks >= 4 && !r.modes.empty()) jackknife(c, i, l, fs_hz, r.modes);
  return r;
}

// ---------------------------------------------------------------------------------------------
// FDD / EFDD

bool FddOptions::is_valid(Index n_samples, double fs_hz, std::string* why) const {
  OptionsCheck c("FddOptions", why);
  return c.require(f_min_hz >= 0.0, "f_min_hz", f_min_hz, "f_min_hz >= 0") &&
         c.require_or_infinite(f_max_hz > f_min_hz, "f_max_hz", f_max_hz, "f_max_hz > f_min_hz") &&
         c.require(f_min_hz < 0.5 * fs_hz, "f_min_hz", f_min_hz, "f_min_hz below the Nyquist frequency " + format_number(0.5 * fs_hz) + " Hz") &&
         c.require(nperseg == 0 || (nperseg >= 16 && nperseg <= n_samples), "nperseg", static_cast<double>(nperseg),
                   "nperseg 0 (chosen) or in [16, " + std::to_string(n_samples) + "] (the record's samples)") &&
         c.require(min_prominence_db >= 0.0, "min_prominence_db", min_prominence_db, "min_prominence_db >= 0") &&
         c.require(efdd_mac > 0.0 && efdd_mac < 1.0, "efdd_mac", efdd_mac, "efdd_mac in (0, 1)");
}

namespace {

// EFDD of the bell [lo, hi] of the first singular value: its correlation function (divided by
// the Hann window's own correlation, which the Welch average multiplies it with), zero
// crossings and extremes between 0.9 and 0.3 of its start (below, the averaged correlation's
// noise, about 1/√segments of its start, takes over).
void efdd(const FddResult& r, Index lo, Index hi, double fs_hz, FddMode& m) {
  const Index nper = r.nperseg, nbins = nper / 2 + 1;
  ComplexVector bell = ComplexVector::Zero(nbins);
  for (Index k = lo; k <= hi; ++k) bell[k] = r.singular_values(k, 0);
  const Vector corr = signal::irfft(bell, nper);
  const Vector w = signal::make_window(signal::Window::hann, nper);
  const Index usable = nper / 2;
  Vector c(usable);
  for (Index t = 0; t < usable; ++t) {
    const double wac = w.head(nper - t).dot(w.tail(nper - t)) / w.squaredNorm();
    c[t] = wac > 0.2 ? corr[t] / wac : 0.0;
    if (wac <= 0.2) {
      c.conservativeResize(t);
      break;
    }
  }
  if (c.size() < 8 || !(c[0] > 0.0)) {
    m.note = "EFDD: no correlation function from the bell";
    return;
  }
  c /= c[0];
  std::vector<double> crossing, ext_t, ext_a;
  Index last = 0;
  for (Index t = 1; t < c.size(); ++t) {
    if ((c[t - 1] > 0.0) != (c[t] > 0.0)) {
      // the extreme of the half cycle just closed
      Index e = last;
      for (Index s = last; s < t; ++s)
        if (std::abs(c[s]) > std::abs(c[e])) e = s;
      if (last > 0) {
        ext_t.push_back(static_cast<double>(e) / fs_hz);
        ext_a.push_back(std::abs(c[e]));
      }
      crossing.push_back((static_cast<double>(t - 1) + c[t - 1] / (c[t - 1] - c[t])) / fs_hz);
      last = t;
    }
  }
  std::vector<double> tt, la;
  for (std::size_t k = 0; k < ext_a.size(); ++k) {
    if (ext_a[k] > 0.9) continue;
    if (ext_a[k] < 0.3) break;
    tt.push_back(ext_t[k]);
    la.push_back(std::log(ext_a[k]));
  }
  // The zero crossings over the same stretch of the correlation function.
  if (!tt.empty()) {
    std::vector<double> kept;
    for (double t : crossing)
      if (t >= tt.front() - 0.5 * (tt.size() > 1 ? tt[1] - tt[0] : 0.0) && t <= tt.back()) kept.push_back(t);
    crossing = kept;
  }
  if (tt.size() < 3 || crossing.size() < 3) {
    m.note = "EFDD: fewer than 3 extremes between 0.9 and 0.3 of the bell's correlation (a wider bell: lower efdd_mac)";
    return;
  }
  auto slope = [](const std::vector<double>& x, const std::vector<double>& v) {
    const double n = static_cast<double>(x.size());
    const double mx = std::accumulate(x.begin(), x.end(), 0.0) / n, mv = std::accumulate(v.begin(), v.end(), 0.0) / n;
    double sxy = 0.0, sxx = 0.0;
    for (std::size_t k = 0; k < x.size(); ++k) {
      sxy += (x[k] - mx) * (v[k] - mv);
      sxx += (x[k] - mx) * (x[k] - mx);
    }
    return sxy / sxx;
  };
  const double sigma = -slope(tt, la);
  std::vector<double> idx, tc;
  for (std::size_t k = 0; k < crossing.size(); ++k) {
    idx.push_back(static_cast<double>(k));
    tc.push_back(crossing[k]);
  }
  const double half_period = slope(idx, tc);
  const double wd = kPi / half_period;
  const double wn = std::sqrt(wd * wd + sigma * sigma);
  m.efdd_frequency_hz = wn / (2.0 * kPi);
  m.efdd_damping_ratio = sigma / wn;
}

}  // namespace

FddResult fdd(const Matrix& y0, double fs_hz, const FddOptions& o) {
  std::string why;
  if (!o.is_valid(y0.rows(), fs_hz, &why)) throw InputError("FDD: " + why);
  check_oma_record(y0, fs_hz, {}, 1, 0.0, std::numeric_limits<double>::infinity(), 0.0);
  const Index n = y0.rows(), l = y0.cols();
  FddResult r;
  Index nper = o.nperseg;
  if (nper == 0) {
    nper = 256;
    while (nper * 2 <= 16384 && std::abs(std::log2(static_cast<double>(nper * 2) / (static_cast<double>(n) / 16.0))) <
                                    std::abs(std::log2(static_cast<double>(nper) / (static_cast<double>(n) / 16.0))))
      nper *= 2;
    nper = std::min(nper, n);
  }
  r.nperseg = nper;
  const Index step = nper / 2, nbins = nper / 2 + 1;
  const Vector w = signal::make_window(signal::Window::hann, nper);
  std::vector<ComplexMatrix> g(static_cast<std::size_t>(nbins), ComplexMatrix::Zero(l, l));
  Index segments = 0;
  ComplexMatrix x(nbins, l);
  for (Index s = 0; s + nper <= n; s += step, ++segments) {
    for (Index a = 0; a < l; ++a) {
      Vector seg = y0.col(a).segment(s, nper);
      seg.array() -= seg.mean();
      x.col(a) = signal::rfft(seg.cwiseProduct(w));
    }
    for (Index k = 0; k < nbins; ++k) g[static_cast<std::size_t>(k)].noalias() += x.row(k).adjoint() * x.row(k);
  }
  const double scale = 2.0 / (fs_hz * w.squaredNorm() * static_cast<double>(segments));
  r.frequency_hz = signal::rfft_frequencies(nper, fs_hz);
  r.singular_values.resize(nbins, l);
  std::vector<ComplexVector> u1(static_cast<std::size_t>(nbins));
  for (Index k = 0; k < nbins; ++k) {
    const double s = (k == 0 || (nper % 2 == 0 && k == nbins - 1)) ? 0.5 * scale : scale;
    Eigen::SelfAdjointEigenSolver<ComplexMatrix> es(g[static_cast<std::size_t>(k)] * s);
    for (Index j = 0; j < l; ++j) r.singular_values(k, j) = std::max(0.0, es.eigenvalues()[l - 1 - j]);
    u1[static_cast<std::size_t>(k)] = es.eigenvectors().col(l - 1).conjugate();
  }
  const double f_hi = std::min(o.f_max_hz, 0.5 * fs_hz);
  Index k_lo = 0, k_hi = nbins - 1;
  while (k_lo < nbins - 1 && r.frequency_hz[k_lo] < o.f_min_hz) ++k_lo;
  while (k_hi > k_lo && r.frequency_hz[k_hi] > f_hi) --k_hi;
  if (k_hi - k_lo < 3) throw InputError("FDD: the band holds fewer than 4 spectral lines (a longer nperseg, or a wider band)");
  const double floor = std::max(r.singular_values.col(0).segment(k_lo, k_hi - k_lo + 1).maxCoeff() * 1e-30, 1e-300);
  Vector db(k_hi - k_lo + 1);
  for (Index k = k_lo; k <= k_hi; ++k) db[k - k_lo] = 10.0 * std::log10(std::max(r.singular_values(k, 0), floor));
  signal::PeakOptions po;
  po.min_prominence = o.min_prominence_db;
  po.max_peaks = o.max_modes;
  for (const signal::Peak& p : signal::find_peaks(db, po, signal::Interpolation::parabolic)) {
    const Index k0 = p.index + k_lo;
    if (k0 == k_lo || k0 == k_hi) continue;
    FddMode m;
    m.frequency_hz = (p.position + static_cast<double>(k_lo)) * fs_hz / static_cast<double>(nper);
    m.shape = shape_quality(u1[static_cast<std::size_t>(k0)]).normalised;
    Index lo = k0, hi = k0;
    // The bell: lines on either side whose singular vector is the peak's (MAC) and whose level is
    // within 20 dB of it (the SDOF's own bell; beyond, noise and the other modes' tails).
    const double level = 0.01 * r.singular_values(k0, 0);
    auto in_bell = [&](Index k) {
      return r.singular_values(k, 0) >= level && mac_of(u1[static_cast<std::size_t>(k)], u1[static_cast<std::size_t>(k0)]) >= o.efdd_mac;
    };
    while (lo - 1 >= k_lo && in_bell(lo - 1)) --lo;
    while (hi + 1 <= k_hi && in_bell(hi + 1)) ++hi;
    m.bell_low_hz = r.frequency_hz[lo];
    m.bell_high_hz = r.frequency_hz[hi];
    efdd(r, lo, hi, fs_hz, m);
    r.modes.push_back(std::move(m));
  }
  return r;
}

// ---------------------------------------------------------------------------------------------
// Free decay, tracking

Index free_decay_start(const Matrix& y, Index window) {
  if (y.rows() < 3 || y.cols() < 1) throw InputError("free decay: the record is too short");
  window = std::max<Index>(1, window | 1);
  Vector e2 = Vector::Zero(y.rows());
  for (Index c = 0; c < y.cols(); ++c) {
    Vector col = y.col(c);
    col.array() -= col.mean();
    e2 += signal::running_rms(col, window).cwiseAbs2();
  }
  const Vector e = e2.cwiseSqrt();
  Index imax = 0;
  e.maxCoeff(&imax);
  std::vector<double> sorted(e.data(), e.data() + e.size());
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 20), sorted.end());
  const double floor = sorted[sorted.size() / 20];
  Index end = imax;
  while (end + 1 < e.size() && e[end] > 2.0 * floor) ++end;
  Index last_rise = imax;
  double low = e[imax];
  for (Index t = imax + 1; t < end; ++t) {
    if (e[t] < low) low = e[t];
    else if (e[t] > 1.02 * low) {
      last_rise = t;
      low = e[t];
    }
  }
  Index start = last_rise;
  for (Index t = last_rise; t < end; ++t)
    if (e[t] > e[start]) start = t;
  return std::min<Index>(y.rows() - 1, start + window / 2);
}

bool TrackingOptions::is_valid(std::string* why) const {
  OptionsCheck c("TrackingOptions", why);
  return c.require(tol_frequency > 0.0 && tol_frequency < 1.0, "tol_frequency", tol_frequency, "tol_frequency in (0, 1)") &&
         c.require(min_mac >= 0.0 && min_mac < 1.0, "min_mac", min_mac, "min_mac in [0, 1)");
}

std::vector<std::vector<int>> track_modes(const std::vector<std::vector<OmaMode>>& windows, const TrackingOptions& o) {
  require_valid(o, "mode tracking");
  struct Track {
    double f;
    ComplexVector shape;
  };
  std::vector<Track> tracks;
  std::vector<std::vector<int>> out;
  for (const auto& modes : windows) {
    std::vector<int> assigned(modes.size(), -1);
    struct Pair {
      double cost;
      std::size_t mode;
      std::size_t track;
    };
    std::vector<Pair> pairs;
    for (std::size_t m = 0; m < modes.size(); ++m)
      for (std::size_t t = 0; t < tracks.size(); ++t) {
        const double df = std::abs(modes[m].frequency_hz - tracks[t].f) / tracks[t].f;
        const bool shapes = modes[m].shape.size() > 0 && modes[m].shape.size() == tracks[t].shape.size();
        const double mac = shapes ? mac_of(modes[m].shape, tracks[t].shape) : 1.0;
        if (df <= o.tol_frequency && (!shapes || mac >= o.min_mac)) pairs.push_back({df + 1.0 - mac, m, t});
      }
    std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.cost < b.cost; });
    std::vector<bool> track_taken(tracks.size(), false);
    for (const Pair& p : pairs) {
      if (assigned[p.mode] >= 0 || track_taken[p.track]) continue;
      assigned[p.mode] = static_cast<int>(p.track);
      track_taken[p.track] = true;
    }
    for (std::size_t m = 0; m < modes.size(); ++m) {
      if (assigned[m] < 0) {
        assigned[m] = static_cast<int>(tracks.size());
        tracks.push_back({modes[m].frequency_hz, modes[m].shape});
      } else {
        tracks[static_cast<std::size_t>(assigned[m])] = {modes[m].frequency_hz, modes[m].shape};
      }
    }
    out.push_back(std::move(assigned));
  }
  return out;
}

}  // namespace viaduct::ident

namespace viaduct::ident {

bool OmaPlan::is_valid(std::string* why) const {
  OptionsCheck c("OmaPlan", why);
  return c.require(decimate >= 1 && decimate <= 50, "decimate", decimate, "decimate in 1..50") &&
         c.require(window_s >= 0.0, "window_s", window_s, "window_s >= 0 (0: the whole record)") &&
         c.require(min_periods >= 0.0, "min_periods", min_periods, "min_periods >= 0") &&
         c.require(decay_rms_s >= 0.0, "decay_rms_s", decay_rms_s, "decay_rms_s >= 0") &&
         (std::isnan(start_s) || std::isnan(end_s) || c.require(end_s > start_s, "end_s", end_s, "end_s > start_s"));
}

std::vector<OmaWindow> identify_output_only(const Matrix& y0, double fs0, double t0_s, const std::vector<std::string>& names,
                                            const OmaPlan& plan) {
  require_valid(plan, "output-only identification");
  // The whole record first (NaN, constant, clipped channels), before decimation hides them.
  check_oma_record(y0, fs0, names, 1, 0.0, std::numeric_limits<double>::infinity(), 0.0);
  Matrix decimated;  // only when decimating: otherwise the record is read where it is, not copied
  double fs = fs0;
  OmaPlan p = plan;
  if (plan.decimate > 1) {
    // The decimating low-pass (scipy.signal.decimate's) passes up to 0.8 of the new Nyquist
    // frequency; above, it bends the modal peaks: the band stops there.
    const double edge = 0.8 * 0.5 * fs0 / plan.decimate;
    if (plan.ssi.f_min_hz >= edge || (std::isfinite(plan.ssi.f_max_hz) && plan.ssi.f_max_hz > edge))
      throw InputError("the band (" + format_number(plan.ssi.f_min_hz) + " to " + format_number(plan.ssi.f_max_hz) +
                       " Hz) reaches above " + format_number(edge) + " Hz, the passband edge of the low-pass that decimating by " +
                       std::to_string(plan.decimate) + " applies (0.8 x the new Nyquist frequency): decimate less");
    if (!std::isfinite(plan.ssi.f_max_hz)) p.ssi.f_max_hz = edge;
    const Index n = (y0.rows() + plan.decimate - 1) / plan.decimate;
    decimated.resize(n, y0.cols());
    for (Index c = 0; c < y0.cols(); ++c) decimated.col(c) = signal::decimate(y0.col(c), plan.decimate);
    fs = fs0 / plan.decimate;
  }
  const Matrix& y = plan.decimate > 1 ? decimated : y0;
  const double t_end_record = t0_s + static_cast<double>(y.rows() - 1) / fs;
  const double from = std::isnan(plan.start_s) ? t0_s : plan.start_s;
  const double to = std::isnan(plan.end_s) ? t_end_record : plan.end_s;
  if (from < t0_s - 0.5 / fs || from >= t_end_record)
    throw InputError("the start " + format_number(from) + " s lies outside the record (" + format_number(t0_s) + " to " +
                     format_number(t_end_record) + " s)");
  auto sample = [&](double t) { return std::clamp<Index>(static_cast<Index>(std::llround((t - t0_s) * fs)), 0, y.rows()); };
  Index i0 = sample(from), i1 = std::min(sample(to) + 1, y.rows());
  const double f_low = p.ssi.f_min_hz;
  const double f_high = p.ssi.f_max_hz;
  std::vector<std::pair<Index, Index>> spans;
  if (plan.ssi.free_decay) {
    const double rms_s = plan.decay_rms_s > 0.0 ? plan.decay_rms_s : f_low > 0.0 ? 2.0 / f_low : 0.5;
    if (std::isnan(plan.start_s)) i0 += free_decay_start(y.middleRows(i0, i1 - i0), std::max<Index>(3, static_cast<Index>(rms_s * fs)));
    spans.push_back({i0, i1});
  } else if (plan.window_s > 0.0) {
    const Index w = static_cast<Index>(std::llround(plan.window_s * fs));
    if (w < 64)
      throw InputError("the window (" + format_number(plan.window_s) + " s) holds " + std::to_string(w) + " samples at " +
                       format_number(fs) + " Hz; at least 64 are needed");
    if (w > i1 - i0) throw InputError("the window (" + format_number(plan.window_s) + " s) is longer than the record (" +
                                      format_number(static_cast<double>(i1 - i0) / fs) + " s)");
    for (Index s = i0; s + w <= i1; s += w) spans.push_back({s, s + w});
  } else {
    spans.push_back({i0, i1});
  }
  FddOptions fo = p.fdd;
  fo.f_min_hz = p.ssi.f_min_hz;
  fo.f_max_hz = p.ssi.f_max_hz;
  std::vector<OmaWindow> out;
  for (const auto& [a, b] : spans) {
    OmaWindow w;
    w.t_start_s = t0_s + static_cast<double>(a) / fs;
    w.t_end_s = t0_s + static_cast<double>(b - 1) / fs;
    try {
      const Matrix piece = y.middleRows(a, b - a);
      check_oma_record(piece, fs, names, 2, f_low, f_high, p.ssi.free_decay ? 0.0 : p.min_periods);
      w.ssi = ssi_cov(piece, fs, p.ssi);
      if (!p.ssi.free_decay) w.warning = stationarity_warning(piece, fs, w.t_start_s);
      if (!w.warning.empty())
        for (OmaMode& m : w.ssi.modes) m.note += std::string(m.note.empty() ? "" : "; ") + "the window is not stationary (see the warning)";
      if (fo.nperseg == 0 || fo.nperseg <= piece.rows()) w.fdd = fdd(piece, fs, fo);
    } catch (const InputError& e) {
      w.error = e.what();
    }
    out.push_back(std::move(w));
  }
  return out;
}

}  // namespace viaduct::ident
