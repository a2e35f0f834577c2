// The fused modal kernel of envelope sweeps (private to src/solve; reached through
// Integrator::run_batch with peaks-only recording, integrator.cpp).
//
// A sweep only keeps each output's maximum |acceleration| and |deflection|. With the modal
// method each case reduces to one tight loop: the modal loads read from a table folded once per
// train (MovingChannels), the exact step of every modal equation (classical modes) or complex
// coordinate (damping that couples the modes, in split real arithmetic), the outputs and their
// running maxima, four speeds in SIMD lanes (complex coordinates: eight where the processor has
// AVX-512; the same numbers on every instruction set). With acceleration histories asked for (a filter is
// applied to them afterwards) they are recorded too, nothing else. Many deflection-type outputs
// (load effects along a span) are taken a block of steps at a time against bounds
// (BlockOutputs). Same model, same step, same values as ModalReduction::integrate up to rounding
// (tests/unit/study/test_modal_peaks.cpp; against the histories: tests/verification/test_assess.cpp).
#include "modal_peaks.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "checks.hpp"
#include "lanes.hpp"
#include "viaduct/core/buffer.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/core/cancel.hpp"

namespace viaduct::solve::detail {

namespace {

constexpr std::size_t W = kLanes;  // cases (speeds of one train) advanced together, one per SIMD lane
// The lane type of N lanes: `lanes` (kLanes: the classical kernel, and the complex one without
// AVX-512) or `lanes8` (kWideLanes: the complex kernel with AVX-512). Templates take the count,
// not the type (a vector type as a template argument would lose its may_alias).
template <std::size_t N>
struct LaneOf;
template <>
struct LaneOf<kLanes> {
  using type = lanes;
};
template <>
struct LaneOf<kWideLanes> {
  using type = lanes8;
};
template <std::size_t N>
using Lanes = typename LaneOf<N>::type;

// The lanes' speeds [m/s] and step counts of `in` (a KernelInput or ComplexInput) as lanes.
template <std::size_t N, class Input>
void lane_speeds(const Input& in, Lanes<N>& v, Lanes<N>& n_steps) {
  for (std::size_t l = 0; l < N; ++l) {
    v[l] = in.v[l];
    n_steps[l] = static_cast<double>(in.n_steps[l]);
  }
}

struct KernelInput {
  const double *c8, *two_zw, *w2;  // per mode: exact step coefficients, 2ζω, ω²
  const double* S;                 // row-major no × nm: station outputs of the modes
  const double *breaks, *coef;     // the folded train (coef: n_pieces + 1 blocks, the last zero)
  std::size_t n_pieces;
  double x_start, dt;
  double v[kWideLanes];       // [m/s] per lane (the first N of a kernel of N lanes)
  Index n_steps[kWideLanes];  // per lane
  Index n_max;        // largest of n_steps
  std::size_t nm, nc, no;  // modes, channels (modes, then residuals), stations
  bool flex;               // residual channels present (static correction)
  double* hist = nullptr;  // when set: acceleration of lane l, output j < nh, step k at (l·nh + j)·stride + k
  std::size_t stride = 0, nh = 0;
  const std::size_t* acc_idx = nullptr;  // the outputs whose acceleration is computed (null: all)
  std::size_t n_acc = 0;
  const OutputSum* sums = nullptr;  // n_sums sums of outputs (OutputSum); their load channels from extra0
  std::size_t n_sums = 0, extra0 = 0, n_extra = 0;
  const double* point = nullptr;    // MovingChannels::point (null without extra channels)
  const double* rbound = nullptr;   // MovingChannels::residual_bounds (null: none)
  std::size_t rb_stride = 0;        // their row: MovingChannels::n_outputs
};

// Raw station accelerations of step k into the history of each lane still running.
template <std::size_t N>
inline void store_history(double* hist, std::size_t stride, std::size_t no, std::size_t j, const Index* n_steps,
                          Index k, const Lanes<N>& av) {
  for (std::size_t l = 0; l < N; ++l)
    if (k <= n_steps[l]) hist[(l * no + j) * stride + static_cast<std::size_t>(k)] = av[l];
}

// c[e][l] = r[l][e]: an N × N block of doubles transposed (pure data movement).
#if defined(__clang__)
#define VIADUCT_SHUFFLE(M, a, b, ...) __builtin_shufflevector(a, b, __VA_ARGS__)
#else
#define VIADUCT_SHUFFLE(M, a, b, ...) __builtin_shuffle(a, b, M{__VA_ARGS__})
#endif
template <std::size_t N>
VIADUCT_ALWAYS_INLINE void transpose(const Lanes<N>* r, Lanes<N>* c) {
  if constexpr (N == 4) {
    typedef long long M __attribute__((vector_size(32)));
    const Lanes<4> t0 = VIADUCT_SHUFFLE(M, r[0], r[1], 0, 4, 2, 6), t1 = VIADUCT_SHUFFLE(M, r[0], r[1], 1, 5, 3, 7),
                   t2 = VIADUCT_SHUFFLE(M, r[2], r[3], 0, 4, 2, 6), t3 = VIADUCT_SHUFFLE(M, r[2], r[3], 1, 5, 3, 7);
    c[0] = VIADUCT_SHUFFLE(M, t0, t2, 0, 1, 4, 5);
    c[1] = VIADUCT_SHUFFLE(M, t1, t3, 0, 1, 4, 5);
    c[2] = VIADUCT_SHUFFLE(M, t0, t2, 2, 3, 6, 7);
    c[3] = VIADUCT_SHUFFLE(M, t1, t3, 2, 3, 6, 7);
  } else {
    static_assert(N == 8, "blocks of 4 or 8 lanes");
    typedef long long M __attribute__((vector_size(64)));
    Lanes<8> t[8], u[8];
    for (std::size_t i = 0; i < 8; i += 2) {  // pairs of rows: (r_i[e], r_i+1[e]) for e even, odd
      t[i] = VIADUCT_SHUFFLE(M, r[i], r[i + 1], 0, 8, 2, 10, 4, 12, 6, 14);
      t[i + 1] = VIADUCT_SHUFFLE(M, r[i], r[i + 1], 1, 9, 3, 11, 5, 13, 7, 15);
    }
    for (std::size_t i = 0; i < 8; i += 4) {  // quadruples: e and e + 4 in the halves
      u[i] = VIADUCT_SHUFFLE(M, t[i], t[i + 2], 0, 1, 8, 9, 4, 5, 12, 13);
      u[i + 1] = VIADUCT_SHUFFLE(M, t[i + 1], t[i + 3], 0, 1, 8, 9, 4, 5, 12, 13);
      u[i + 2] = VIADUCT_SHUFFLE(M, t[i], t[i + 2], 2, 3, 10, 11, 6, 7, 14, 15);
      u[i + 3] = VIADUCT_SHUFFLE(M, t[i + 1], t[i + 3], 2, 3, 10, 11, 6, 7, 14, 15);
    }
    for (std::size_t e = 0; e < 4; ++e) {  // rows 0–3 and 4–7 joined
      c[e] = VIADUCT_SHUFFLE(M, u[e], u[e + 4], 0, 1, 2, 3, 8, 9, 10, 11);
      c[e + 4] = VIADUCT_SHUFFLE(M, u[e], u[e + 4], 4, 5, 6, 7, 12, 13, 14, 15);
    }
  }
}

// A folded train's pieces under N lanes' heads (both cursors below): each lane's piece and the
// break that ends it, and the extra channels' values at a break hit exactly
// (MovingChannels::point, valid for one step).
template <std::size_t N>
struct PieceTrack {
  const double *breaks = nullptr, *coef = nullptr;
  std::size_t n_pieces = 0, nc = 0, nload = 0;  // pieces, channels, load channels
  const double* point = nullptr;
  std::size_t nx = 0;
  Lanes<N>* pt = nullptr;
  std::size_t ip[N];
  double next[N];

  // The folded train of `in` (a KernelInput or ComplexInput): nc channels, nload of them loads;
  // the extra channels' point values into pt.
  template <class Input>
  void bind_track(const Input& in, std::size_t n_channels, std::size_t n_load, Lanes<N>* pt_) {
    breaks = in.breaks;
    coef = in.coef;
    n_pieces = in.n_pieces;
    nc = n_channels;
    nload = n_load;
    if (in.point) point = in.point, nx = in.n_extra, pt = pt_;
  }
  // Lane l's piece at head position x (a lane's pieces only move forward), and its end.
  VIADUCT_ALWAYS_INLINE std::size_t find_piece(std::size_t l, double x) {
    std::size_t i = ip[l];
    while (i < n_pieces && x >= breaks[i + 1]) ++i;
    ip[l] = i;
    next[l] = i < n_pieces ? breaks[i + 1] : std::numeric_limits<double>::infinity();
    return i;
  }
  // The extra channels' point values of lane l when x is piece i's break exactly.
  VIADUCT_ALWAYS_INLINE void take_point(std::size_t l, double x, std::size_t i) {
    if (point && x == breaks[i])
      for (std::size_t e = 0; e < nx; ++e) pt[e][l] = point[i * nx + e];
  }
};

// The folded train's load channels of W lanes along the head position: per lane the piece it is
// on and, for every channel, the value and forward differences f, d1, d2, d3 of the cubic at the
// lane's step (and, for the nr residual channels, the curvature term v²·g'' and its difference),
// re-initialised from the piece's coefficients whenever the lane's head crosses a breakpoint.
// N lanes: f[k] holds channel k of every lane.
template <std::size_t N>
struct LoadCursorT : PieceTrack<N> {
  using L = Lanes<N>;
  using T = PieceTrack<N>;
  using T::breaks, T::coef, T::n_pieces, T::nc, T::nload, T::nx, T::pt, T::ip, T::next;
  static constexpr std::size_t W = N;
  std::size_t nr = 0;  // residuals used
  L *f = nullptr, *d1 = nullptr, *d2 = nullptr, *d3 = nullptr, *c = nullptr, *dc = nullptr;
  double h[W], v2[W];
  // The channel ranges [a, b) set at each piece (none kept: all nc; or what the caller reads step
  // by step: keep()); the others hold nothing.
  std::size_t kept[4][2] = {}, n_kept = 0;
  // The residuals whose curvature is kept (null: all nr): those whose acceleration is computed.
  const std::size_t* curv = nullptr;
  std::size_t n_curv = 0;

  // Lane l at head position x: find its piece, set the values and differences there.
  VIADUCT_ALWAYS_INLINE void reinit(std::size_t l, double x) {
    const std::size_t i = this->find_piece(l, x);
    const double s = i < n_pieces ? x - breaks[i] : 0.0, hh = h[l], h2 = hh * hh, h3 = h2 * hh;
    const double* d = coef + i * 4 * nc;
    // W channels at a time in vector registers (the same operations in the same order as the
    // one-channel loop below, which takes the rest: the same values), stored into lane l.
    const double c1 = 2.0 * s * hh + h2, c2 = 3.0 * s * s * hh + 3.0 * s * h2 + h3, c3 = 6.0 * s * h2 + 6.0 * h3;
    if (!n_kept) set_channels(0, nc, d, s, hh, h2, h3, c1, c2, c3, l);
    for (std::size_t r = 0; r < n_kept; ++r) set_channels(kept[r][0], kept[r][1], d, s, hh, h2, h3, c1, c2, c3, l);
    for (std::size_t n = 0; n < (curv ? n_curv : nr); ++n) {
      const std::size_t j = curv ? curv[n] : n;
      const double a2 = d[2 * nc + nload + j], a3 = d[3 * nc + nload + j];
      c[j][l] = v2[l] * (2.0 * a2 + 6.0 * a3 * s);
      dc[j][l] = v2[l] * 6.0 * a3 * hh;
    }
    this->take_point(l, x, i);
  }
  // Channels [a, b) of lane l at place s on the piece whose coefficients d are.
  VIADUCT_ALWAYS_INLINE void set_channels(std::size_t a, std::size_t b, const double* d, double s, double hh, double h2,
                                          double h3, double c1, double c2, double c3, std::size_t l) {
    std::size_t k0 = a;
    for (; k0 + W <= b; k0 += W) {
      L a0, a1, a2, a3;
      std::memcpy(&a0, d + k0, sizeof a0);
      std::memcpy(&a1, d + nc + k0, sizeof a1);
      std::memcpy(&a2, d + 2 * nc + k0, sizeof a2);
      std::memcpy(&a3, d + 3 * nc + k0, sizeof a3);
      const L fv = a0 + s * (a1 + s * (a2 + s * a3)), v1 = a1 * hh + a2 * c1 + a3 * c2, v2_ = 2.0 * a2 * h2 + a3 * c3,
              v3 = 6.0 * a3 * h3;
      for (std::size_t e = 0; e < W; ++e) f[k0 + e][l] = fv[e], d1[k0 + e][l] = v1[e], d2[k0 + e][l] = v2_[e], d3[k0 + e][l] = v3[e];
    }
    for (std::size_t k = k0; k < b; ++k) {
      const double a0 = d[k], a1 = d[nc + k], a2 = d[2 * nc + k], a3 = d[3 * nc + k];
      f[k][l] = a0 + s * (a1 + s * (a2 + s * a3));
      d1[k][l] = a1 * hh + a2 * (2.0 * s * hh + h2) + a3 * (3.0 * s * s * hh + 3.0 * s * h2 + h3);
      d2[k][l] = 2.0 * a2 * h2 + a3 * (6.0 * s * h2 + 6.0 * h3);
      d3[k][l] = 6.0 * a3 * h3;
    }
  }
  // The folded train of `in` (a KernelInput or ComplexInput): nc channels, nload of them loads,
  // nr residuals used; the values and differences in f … dc, extra channels at break hits in pt.
  template <class Input>
  void bind(const Input& in, std::size_t n_channels, std::size_t n_load, std::size_t n_res, L* f_, L* d1_, L* d2_,
            L* d3_, L* c_, L* dc_, L* pt_) {
    this->bind_track(in, n_channels, n_load, pt_);
    nr = n_res;
    f = f_, d1 = d1_, d2 = d2_, d3 = d3_, c = c_, dc = dc_;
    n_kept = 0;
    // Only the accelerations computed read a residual's curvature: the others' is not set up at
    // each piece (the 31 stations along a span of docs/benchmarks.md: 127 residuals, a few read).
    if (in.acc_idx && n_res) curv = in.acc_idx, n_curv = in.n_acc;
  }
  // Only channel ranges [a, b) (at most four) are set at each piece from now. A range of fewer
  // than W channels is widened to W within [0, nc), and ranges that touch are joined, so that
  // set_channels takes them W at a time in vector registers: a channel set that nothing reads
  // holds its piece's values as any set channel does (on the 31 stations along a span of
  // docs/benchmarks.md the ranges [0, 3) [101, 105) [105, 107) [107, 109), eleven channels one at
  // a time at each of the 2 million crossings, became [0, 8) [101, 109)).
  void keep(const std::size_t (&r)[4][2]) {
    std::size_t w[4][2], n = 0;
    for (std::size_t i = 0; i < 4; ++i) {
      std::size_t a = r[i][0], b = r[i][1];
      if (b <= a) continue;
      if (b - a < W) {
        b = std::min(nc, a + W);
        a = b >= W ? std::min(a, b - W) : 0;
      }
      std::size_t k = n++;  // insertion by start
      for (; k > 0 && w[k - 1][0] > a; --k) w[k][0] = w[k - 1][0], w[k][1] = w[k - 1][1];
      w[k][0] = a, w[k][1] = b;
    }
    n_kept = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (n_kept && w[i][0] <= kept[n_kept - 1][1]) {
        kept[n_kept - 1][1] = std::max(kept[n_kept - 1][1], w[i][1]);
      } else {
        kept[n_kept][0] = w[i][0], kept[n_kept][1] = w[i][1], ++n_kept;
      }
    }
  }
  // Channels [a, b) to the next step: value and differences, three additions each.
  VIADUCT_ALWAYS_INLINE void step_channels(std::size_t a, std::size_t b) {
    for (std::size_t k = a; k < b; ++k) {
      f[k] += d1[k];
      d1[k] += d2[k];
      d2[k] += d3[k];
    }
  }
  // Every lane at the path's start, speeds v [m/s], step dt.
  VIADUCT_ALWAYS_INLINE void start(const double* v, double dt, double x_start) {
    for (std::size_t l = 0; l < W; ++l) {
      ip[l] = 0;
      h[l] = v[l] * dt;
      v2[l] = v[l] * v[l];
      reinit(l, x_start);
    }
  }
  // One step: three additions per channel (n_ch, n_res: the caller's sizes, constants in the
  // unrolled kernels), then the lanes whose head X crossed a breakpoint start their new piece. The
  // residuals' curvature advances only for the outputs in acc_idx when it is given (the others'
  // accelerations are not read; reinit sets every one afresh).
  // Channels [x0, x1) advance too (the classical kernel's extra channels: it advances the
  // residuals itself, with its outputs, and passes n_ch = the modes).
  VIADUCT_ALWAYS_INLINE void advance(std::size_t n_ch, std::size_t n_res, const L& X,
                                     const std::size_t* acc_idx = nullptr, std::size_t n_acc = 0, std::size_t x0 = 0,
                                     std::size_t x1 = 0) {
    for (std::size_t e = 0; e < nx; ++e) pt[e] = L{};
    step_channels(0, n_ch);
    step_channels(x0, x1);
    if (!acc_idx) {
      for (std::size_t j = 0; j < n_res; ++j) c[j] += dc[j];
    } else if (n_res) {
      for (std::size_t a = 0; a < n_acc; ++a) c[acc_idx[a]] += dc[acc_idx[a]];
    }
    for (std::size_t l = 0; l < W; ++l)
      if (X[l] >= next[l]) reinit(l, X[l]);
  }
};
using LoadCursor = LoadCursorT<kLanes>;

// The folded train's load channels of N lanes, each value evaluated afresh every step from its
// piece's cubic (Horner in s = X − the piece's start) instead of advanced by forward differences:
// for the complex kernel, whose lanes enter a new piece about every other step with a discrete
// track (Old Guadiana: 4461 pieces of 359 channels), where LoadCursorT re-initialised four
// rows of differences at each crossing and advanced three every step. Here a lane's channels
// are read once a step, eight (N) at a time, and N lanes' blocks are transposed into the
// channels' values across the lanes. The residuals' curvature v²·g'' (of the outputs whose
// acceleration is computed) and the extra channels' point values at a break hit exactly as
// LoadCursorT's.
template <std::size_t N>
struct DirectCursor : PieceTrack<N> {
  using L = Lanes<N>;
  using T = PieceTrack<N>;
  using T::breaks, T::coef, T::n_pieces, T::nc, T::nload, T::nx, T::pt, T::ip, T::next;
  L* c = nullptr;  // residual curvatures across the lanes
  const std::size_t* curv = nullptr;
  std::size_t n_curv = 0;
  double v2[N];

  template <class Input>
  void bind(const Input& in, std::size_t n_channels, std::size_t n_load, std::size_t n_res, L* c_, L* pt_) {
    this->bind_track(in, n_channels, n_load, pt_);
    c = c_;
    if (n_res) {
      curv = in.acc_idx;  // null: every residual's curvature
      n_curv = in.acc_idx ? in.n_acc : n_res;
    }
  }
  // Lane l's piece at head position x, and its point values there.
  VIADUCT_ALWAYS_INLINE void locate(std::size_t l, double x) { this->take_point(l, x, this->find_piece(l, x)); }
  VIADUCT_ALWAYS_INLINE void start(const double* v, double x_start) {
    for (std::size_t l = 0; l < N; ++l) {
      ip[l] = 0;
      v2[l] = v[l] * v[l];
      locate(l, x_start);
    }
  }
  // One step to head positions X: the point values last one step.
  VIADUCT_ALWAYS_INLINE void advance(const L& X) {
    for (std::size_t e = 0; e < nx; ++e) pt[e] = L{};
    for (std::size_t l = 0; l < N; ++l)
      if (X[l] >= next[l]) locate(l, X[l]);
  }
  // Every channel's value at head positions X across the lanes, out[k] for k < nc rounded up to
  // N (the padding's values are zero), and the residuals' curvatures.
  VIADUCT_ALWAYS_INLINE void values(const L& X, L* out) {
    double s[N];
    const double* d[N];
    for (std::size_t l = 0; l < N; ++l) {
      const std::size_t i = ip[l];
      s[l] = i < n_pieces ? X[l] - breaks[i] : 0.0;
      d[l] = coef + i * 4 * nc;
    }
    const std::size_t nfull = nc / N;
    for (std::size_t b = 0; b < nfull; ++b) {
      L r[N];
      for (std::size_t l = 0; l < N; ++l) {
        L a0, a1, a2, a3;
        const double* q = d[l] + b * N;
        std::memcpy(&a0, q, sizeof a0);
        std::memcpy(&a1, q + nc, sizeof a1);
        std::memcpy(&a2, q + 2 * nc, sizeof a2);
        std::memcpy(&a3, q + 3 * nc, sizeof a3);
        r[l] = a0 + s[l] * (a1 + s[l] * (a2 + s[l] * a3));
      }
      transpose<N>(r, out + b * N);
    }
    if (const std::size_t k0 = nfull * N; k0 < nc) {
      L r[N];
      for (std::size_t l = 0; l < N; ++l) {
        r[l] = L{};
        for (std::size_t k = k0; k < nc; ++k) {
          const double* q = d[l] + k;
          r[l][k - k0] = q[0] + s[l] * (q[nc] + s[l] * (q[2 * nc] + s[l] * q[3 * nc]));
        }
      }
      transpose<N>(r, out + nfull * N);
    }
    for (std::size_t n = 0; n < n_curv; ++n) {
      const std::size_t j = curv ? curv[n] : n;
      for (std::size_t l = 0; l < N; ++l) {
        const double* q = d[l] + nload + j;
        c[j][l] = v2[l] * (2.0 * q[2 * nc] + 6.0 * q[3 * nc] * s[l]);
      }
    }
  }
};

// The accelerations of step k (the coordinates' share aj plus the residual's curvature c when
// flex), of every output or of those in acc_idx: recorded when hist is set, their running maxima
// |a| in ma.
template <std::size_t N, class L = Lanes<N>>
VIADUCT_ALWAYS_INLINE void emit_accelerations(std::size_t no, bool flex, const L* aj, const L* c, L* ma, double* hist,
                                              std::size_t stride, std::size_t nh, const Index* n_steps, Index k,
                                              const L& live, bool all_live, const std::size_t* acc_idx,
                                              std::size_t n_acc) {
  const L zero = {};
  const std::size_t n = acc_idx ? n_acc : no;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = acc_idx ? acc_idx[i] : i;
    L av = aj[j];
    if (flex) av += c[j];
    if (hist && j < nh) store_history<N>(hist, stride, nh, j, n_steps, k, av);
    av = av < zero ? -av : av;
    if (!all_live) av = live * av;
    ma[j] = av > ma[j] ? av : ma[j];
  }
}

// Station outputs of step k: the coordinates' share dj, aj plus the static correction's
// residuals (deflection f_res, acceleration c) when flex; recorded when hist is set; running
// maxima of the deflection md and of its negative mn (signed extremes: a bearing's uplift, a
// hogging moment) and of |acceleration| ma (a lane past its own last step, live = 0, keeps them).
template <std::size_t N, class L = Lanes<N>>
VIADUCT_ALWAYS_INLINE void emit_stations(std::size_t no, bool flex, const L* dj, const L* aj, const L* f_res, const L* c,
                                         L* md, L* mn, L* ma, double* hist, std::size_t stride, std::size_t nh,
                                         const Index* n_steps, Index k, const L& live, bool all_live,
                                         const std::size_t* acc_idx = nullptr, std::size_t n_acc = 0) {
  // Plain loops: the same with two lambdas per output made the 31-station sweep of
  // docs/benchmarks.md three times as slow (measured: 15.6 s against 5.5 s on one thread).
  for (std::size_t j = 0; j < no; ++j) {
    L dv = dj[j];
    if (flex) dv += f_res[j];
    if (!all_live) dv = live * dv;  // 1·x = x: the mask matters only once a lane has finished
    const L nv = -dv;
    md[j] = dv > md[j] ? dv : md[j];
    mn[j] = nv > mn[j] ? nv : mn[j];
  }
  emit_accelerations<N>(no, flex, aj, c, ma, hist, stride, nh, n_steps, k, live, all_live, acc_idx, n_acc);
}

// The running state of the sums of outputs (OutputSum), W lanes each: signed extremes, and the
// trapezoidal integral of the acc_integral output with its last acceleration.
template <std::size_t N>
struct SumStateT {
  using L = Lanes<N>;
  std::vector<double> buf;
  L *hi = nullptr, *lo = nullptr, *vi = nullptr, *al = nullptr;
  L* pt = nullptr;  // the extra channels' point values of the current step (LoadCursor::pt)
  SumStateT(std::size_t n, std::size_t n_extra) : buf((4 * n + n_extra + 1) * N, 0.0) {
    L* at = align_lanes<L>(buf.data());
    hi = at, lo = hi + n, vi = lo + n, al = vi + n, pt = al + n;
    const L zero = {}, inf = zero + std::numeric_limits<double>::infinity();
    for (std::size_t s = 0; s < n; ++s) hi[s] = -inf, lo[s] = inf, vi[s] = al[s] = zero;
  }
};
using SumState = SumStateT<kLanes>;

// Sums of step k from the outputs' coordinate shares dj, aj, their static-correction residuals
// (f_res, c: when flex) and the extra load channels; lanes past their last step (live = 0) keep
// their extremes. The integral starts at rest (step 0) and adds dt·(a₀ + a₁)/2 a step.
// disp_total: dj holds each output's deflection-type value with its residual already (the
// classical kernel's outputs_pass), so f_res is not added to it again.
template <std::size_t N, class L = Lanes<N>>
VIADUCT_ALWAYS_INLINE void emit_sums(const OutputSum* sums, std::size_t n_sums, bool flex, const L* dj, const L* aj,
                                     const L* f_res, const L* c, const L* f_extra, double half_dt, Index k,
                                     const L& live, SumStateT<N>& st, bool disp_total = false) {
  const L zero = {};
  // The live lanes (live: 1 or 0) as a bit mask, once a step, from live's bits by integer
  // operations; the extremes below are a maximum and a minimum (NaN keeps the extreme), then a
  // bitwise choice between them and the old extremes. (A vector select on the comparisons inside
  // the loop was built as a compare and branch per lane by GCC 12 for eight lanes, which also
  // fails on a 512-bit comparison kept as a vector here.)
  typedef long long M __attribute__((vector_size(sizeof(L))));
  const M lb = (M)live, on = (lb | -lb) >> 63;
  for (std::size_t s = 0; s < n_sums; ++s) {
    const OutputSum& o = sums[s];
    L y = zero;
    if (o.disp >= 0) {
      y += dj[o.disp];
      if (flex && !disp_total) y += f_res[o.disp];
    }
    if (o.acc >= 0) {
      y += aj[o.acc];
      if (flex) y += c[o.acc];
    }
    if (o.acc_integral >= 0) {
      L a = aj[o.acc_integral];
      if (flex) a += c[o.acc_integral];
      if (k > 0) st.vi[s] += half_dt * (st.al[s] + a);
      st.al[s] = a;
      y += st.vi[s];
    }
    if (o.load_channel >= 0) y += f_extra[o.load_channel] + st.pt[o.load_channel];
    const L h0 = st.hi[s], l0 = st.lo[s], h1 = y > h0 ? y : h0, l1 = y < l0 ? y : l0;
    st.hi[s] = (L)(((M)h1 & on) | ((M)h0 & ~on));
    st.lo[s] = (L)(((M)l1 & on) | ((M)l0 & ~on));
  }
}

// The classical kernel's outputs of step k, in one pass over them: each output's share of the
// modes (its row of S over q, in the modes' order) plus, with FLEX, its residual f_res, into the
// signed extremes md, mn (as emit_stations), outputs [j0, j1); with KEEP the value is kept in dj
// for the sums (the outputs they read, [k0, k1) in kernel_body; emit_sums with disp_total:
// (0 + d) + r there before, 0 + (d + r) now, the same number). With
// FLEX the residual's forward differences then advance to the next step (f_res, r1, r2 from r1,
// r2, r3: what LoadCursor::advance does to every channel, the same additions in the same order;
// here the state is read and written once a step instead of three times). The live mask is
// applied always (1·x = x, NaN and −0 included).
template <std::size_t N, std::size_t NM, bool FLEX, bool KEEP, class L = Lanes<N>>
VIADUCT_ALWAYS_INLINE void outputs_pass(std::size_t nm_, std::size_t j0, std::size_t j1, const double* S, const L* q,
                                        L* dj, L* f_res, L* r1, L* r2, const L* r3, L* md,
                                        L* mn, const L& live) {
  const std::size_t nm = NM ? NM : nm_;
  const L zero = {};
  for (std::size_t j = j0; j < j1; ++j) {
    const double* sj = S + j * nm;
    L d = zero;
    for (std::size_t i = 0; i < nm; ++i) d += sj[i] * q[i];
    if constexpr (FLEX) {
      const L fr = f_res[j], a1 = r1[j], a2 = r2[j];
      d += fr;
      f_res[j] = fr + a1;
      r1[j] = a1 + a2;
      r2[j] = a2 + r3[j];
    }
    if constexpr (KEEP) dj[j] = d;
    const L dv = live * d, nv = -dv;
    md[j] = dv > md[j] ? dv : md[j];
    mn[j] = nv > mn[j] ? nv : mn[j];
  }
}

// Outputs [j0, j1) through outputs_pass, with or without the residual (flex).
template <std::size_t N, std::size_t NM, bool KEEP, class L = Lanes<N>>
VIADUCT_ALWAYS_INLINE void outputs_range(bool flex, std::size_t nm, std::size_t j0, std::size_t j1, const double* S,
                                         const L* q, L* dj, L* f_res, L* r1, L* r2, const L* r3,
                                         L* md, L* mn, const L& live) {
  if (flex) outputs_pass<N, NM, true, KEEP>(nm, j0, j1, S, q, dj, f_res, r1, r2, r3, md, mn, live);
  else outputs_pass<N, NM, false, KEEP>(nm, j0, j1, S, q, dj, f_res, r1, r2, r3, md, mn, live);
}

// The deflection-type outputs of the classical kernel (deflections, moments, shears, rotations:
// those no sum reads step by step) taken a block of B steps at a time, per lane and group of N
// outputs (issue #40: a span's load effects every 0.5 m, about a hundred outputs, each once a
// step cost half the run). As the steps run, the block keeps the modal coordinates, their ranges,
// and each lane's piece of the folded train and place on it. Then, per lane and group, a bound of
// the outputs over the block (each mode's share at the ends of its coordinate's range; the
// residual's bounds over the pieces the lane passes, MovingChannels::residual_bounds) is compared
// with the signed extremes so far, and the block is evaluated only where it may reach beyond them
// (on that job about a third of the lanes' groups). An evaluated step is the sum over the modes
// in their order, as the step-by-step path takes it, plus the residual's cubic by Horner at the
// lane's place (the step-by-step path advances it by forward differences from the same value at
// the piece's start: the same to rounding). The bounds carry a margin of 1e-10 of the magnitudes they add, far above
// the rounding of the few operations on either side, so a block left out holds no value beyond the
// extremes. A NaN in the modes' bound fails the check (the block is evaluated); a NaN residual
// bound (only from NaN coefficients) is passed over: that piece's values are NaN and enter the
// extremes on neither path.
template <std::size_t N, std::size_t NM>
struct BlockOutputs {
  using L = Lanes<N>;
  static constexpr std::size_t B = 16, kMaxModes = 16;  // steps a block; modes taken (more: step by step)
  std::size_t nm = 0, no = 0, nc = 0, n_pieces = 0;
  bool flex = false;
  const double *coef = nullptr, *breaks = nullptr, *rb = nullptr;
  std::size_t rbs = 0;  // rb's row
  std::size_t range[2][2] = {}, n_ranges = 0;  // output ranges [a, b) taken here, each of N or more
  std::vector<double> st;      // S transposed: mode i's share of output j at i·no + j
  std::vector<double> hi, lo;  // lane l's running maximum of output j and of its negative at l·no + j
  std::vector<double> qb;      // the block's coordinates: step t, mode i, lane l at (t·nm + i)·N + l
  L qhi[kMaxModes], qlo[kMaxModes];  // their ranges over the block so far
  std::size_t pb[B][N] = {};  // the block's pieces and places on them (step, lane)
  double sb[B][N] = {};
  Index first = 0;  // the block's first step
  std::size_t n = 0;

  // The outputs [a, b) join the block path when they are N or more.
  VIADUCT_ALWAYS_INLINE bool take(std::size_t a, std::size_t b) {
    if (b < a + N) return false;
    range[n_ranges][0] = a, range[n_ranges][1] = b, ++n_ranges;
    return true;
  }
  VIADUCT_ALWAYS_INLINE void bind(const KernelInput& in, std::size_t nm_, std::size_t no_, bool flex_) {
    nm = NM ? NM : nm_, no = no_, nc = in.nc, n_pieces = in.n_pieces, flex = flex_, coef = in.coef, breaks = in.breaks;
    rb = in.rbound, rbs = in.rb_stride;
    st.assign(nm * no, 0.0);
    for (std::size_t j = 0; j < no; ++j)
      for (std::size_t i = 0; i < nm; ++i) st[i * no + j] = in.S[j * nm + i];
    hi.assign(N * no, 0.0), lo.assign(N * no, 0.0), qb.assign(B * nm * N, 0.0);
  }
  // Step k's coordinates q and the lanes' pieces ip at head positions X.
  VIADUCT_ALWAYS_INLINE void record(Index k, const L* q, const std::size_t* ip, const L& X) {
    if (!n_ranges) return;
    if (n == 0) {
      first = k;
      for (std::size_t i = 0; i < nm; ++i) qhi[i] = qlo[i] = q[i];
    }
    for (std::size_t i = 0; i < nm; ++i) {
      std::memcpy(qb.data() + (n * nm + i) * N, &q[i], sizeof(L));
      qhi[i] = q[i] > qhi[i] ? q[i] : qhi[i];
      qlo[i] = q[i] < qlo[i] ? q[i] : qlo[i];
    }
    for (std::size_t l = 0; l < N; ++l) pb[n][l] = ip[l], sb[n][l] = ip[l] < n_pieces ? X[l] - breaks[ip[l]] : 0.0;
    ++n;
  }
  // The block's steps up to each lane's last (n_steps), when full or at the end (force).
  VIADUCT_ALWAYS_INLINE void flush(const Index* n_steps, bool force) {
    if (n == 0 || (n < B && !force)) return;
    for (std::size_t l = 0; l < N; ++l) {
      // a lane ending within the block: its first nv steps, bounded by the whole block's ranges
      const Index nv = std::min<Index>(static_cast<Index>(n), n_steps[l] - first + 1);
      if (nv > 0) lane(l, static_cast<std::size_t>(nv));
    }
    n = 0;
  }
  // Outputs of the ranges into md, mn as the kernel lays them out (output j, lane l at j·N + l).
  VIADUCT_ALWAYS_INLINE void finish(double* md, double* mn) const {
    for (std::size_t r = 0; r < n_ranges; ++r)
      for (std::size_t j = range[r][0]; j < range[r][1]; ++j)
        for (std::size_t l = 0; l < N; ++l) md[j * N + l] = hi[l * no + j], mn[j * N + l] = lo[l * no + j];
  }

 private:
  VIADUCT_ALWAYS_INLINE static void ld(L& v, const double* p) { std::memcpy(&v, p, sizeof v); }
  // Every lane of a at most b's (NaN: false): the comparison's lanes folded by halves with
  // bitwise and, one test at the end (a test and branch per lane was built).
  VIADUCT_ALWAYS_INLINE static bool all_le(const L& a, const L& b) {
    using M = decltype(a <= b);
    M m = a <= b;
    if constexpr (N == 8) {
      m &= VIADUCT_SHUFFLE(M, m, m, 4, 5, 6, 7, 0, 1, 2, 3);
      m &= VIADUCT_SHUFFLE(M, m, m, 2, 3, 0, 1, 6, 7, 4, 5);
      m &= VIADUCT_SHUFFLE(M, m, m, 1, 0, 3, 2, 5, 4, 7, 6);
    } else {
      static_assert(N == 4, "blocks of 4 or 8 lanes");
      m &= VIADUCT_SHUFFLE(M, m, m, 2, 3, 0, 1);
      m &= VIADUCT_SHUFFLE(M, m, m, 1, 0, 3, 2);
    }
    return m[0] != 0;
  }
  // Lane l's first nv steps of the block, against the bound (the coordinates' ranges over the
  // block hold those of its first nv steps).
  VIADUCT_ALWAYS_INLINE void lane(std::size_t l, std::size_t nv) {
    double qmax[kMaxModes], qmin[kMaxModes], qabs[kMaxModes];
    for (std::size_t i = 0; i < nm; ++i) {
      qmax[i] = qhi[i][l], qmin[i] = qlo[i][l];
      qabs[i] = std::max(std::abs(qmax[i]), std::abs(qmin[i]));
    }
    // The pieces passed (a lane's pieces only move forward; before the first break: no bound).
    const std::size_t p0 = pb[0][l], p1 = pb[nv - 1][l];
    const bool bounded = !flex || (rb && sb[0][l] >= 0.0);
    // Up to 64 groups checked first, their outcomes as bits, then those that may exceed evaluated:
    // no branch between the checks, which then overlap (with a branch per group, taken about one
    // time in five, the 31-station job of docs/benchmarks.md took 1.44 s on one thread, 1.41 s now).
    // A check reads the extremes before this block's evaluations: of an overlapping group's
    // outputs, older and so no larger, a bound compared with them is still a bound.
    for (std::size_t r = 0; r < n_ranges; ++r) {
      const std::size_t a = range[r][0], b = range[r][1], ng = (b - a + N - 1) / N;
      for (std::size_t c0 = 0; c0 < ng; c0 += 64) {
        const std::size_t c1 = std::min(ng, c0 + 64);
        std::uint64_t need = 0;
        for (std::size_t c = c0; c < c1; ++c) {
          const std::size_t g = std::min(a + c * N, b - N);  // the last group overlaps its neighbour
          const bool may = !bounded || may_exceed(l, g, qmax, qmin, qabs, p0, p1);
          need |= static_cast<std::uint64_t>(may) << (c - c0);
        }
        for (; need; need &= need - 1) {
          const std::size_t c = c0 + static_cast<std::size_t>(__builtin_ctzll(need));
          evaluate(l, std::min(a + c * N, b - N), nv);
        }
      }
    }
  }
  // Whether outputs [g, g + N) of lane l may reach beyond their extremes over the block (pieces
  // p0 … p1).
  VIADUCT_ALWAYS_INLINE bool may_exceed(std::size_t l, std::size_t g, const double* qmax, const double* qmin,
                                        const double* qabs, std::size_t p0, std::size_t p1) const {
    const L zero = {};
    L ub = zero, lb = zero, sc = zero;
    for (std::size_t i = 0; i < (NM ? NM : nm); ++i) {
      L s;
      ld(s, st.data() + i * no + g);
      const L a = s * qmax[i], c = s * qmin[i];
      ub += a > c ? a : c;
      lb += a < c ? a : c;
      sc += (s < zero ? -s : s) * qabs[i];
    }
    if (flex) {
      const L inf = zero + std::numeric_limits<double>::infinity();
      L rub = -inf, rlb = inf;
      for (std::size_t p = p0; p <= p1; ++p) {
        if (p >= n_pieces) {  // past the train's end: no load, a residual of 0
          rub = rub > zero ? rub : zero, rlb = rlb < zero ? rlb : zero;
          break;
        }
        L h, w;
        ld(h, rb + (2 * p) * rbs + g), ld(w, rb + (2 * p + 1) * rbs + g);
        rub = h > rub ? h : rub;
        rlb = w < rlb ? w : rlb;
      }
      ub += rub, lb += rlb;
    }
    const L margin = 1e-10 * sc;
    L H, Lo;
    ld(H, hi.data() + l * no + g), ld(Lo, lo.data() + l * no + g);
    return !(all_le(ub + margin, H) & all_le(margin - lb, Lo));  // both tests, no branch between
  }
  VIADUCT_ALWAYS_INLINE void evaluate(std::size_t l, std::size_t g, std::size_t nv) {
    const L zero = {};
    L H, Lo, sv[kMaxModes];
    ld(H, hi.data() + l * no + g), ld(Lo, lo.data() + l * no + g);
    for (std::size_t i = 0; i < nm; ++i) ld(sv[i], st.data() + i * no + g);
    for (std::size_t t = 0; t < nv; ++t) {
      L d = zero;
      const std::size_t m = NM ? NM : nm;
      for (std::size_t i = 0; i < m; ++i) d += sv[i] * qb[(t * m + i) * N + l];
      if (flex) {
        const double s = sb[t][l], *c = coef + pb[t][l] * 4 * nc + nm + g;
        L a0, a1, a2, a3;
        ld(a0, c), ld(a1, c + nc), ld(a2, c + 2 * nc), ld(a3, c + 3 * nc);
        d += a0 + s * (a1 + s * (a2 + s * a3));
      }
      const L nd = -d;
      H = d > H ? d : H;
      Lo = nd > Lo ? nd : Lo;
    }
    std::memcpy(hi.data() + l * no + g, &H, sizeof H);
    std::memcpy(lo.data() + l * no + g, &Lo, sizeof Lo);
  }
};

// N cases in lock-step (four, or eight with AVX-512). Per lane, the channel values along the
// current piece are advanced by forward differences (the load is a cubic in X and X advances by
// v·dt per step: three additions per channel and step, exact up to rounding), re-initialised from
// the piece's coefficients whenever the lane's head crosses a breakpoint. Every quantity is a
// Lanes<N> value, so the arithmetic runs on all N cases at once (each lane's the same operations
// whatever N). NM, NC, NO > 0 fix the sizes at compile time (the
// common small bases); 0 reads them from `in`. Only the residual channels' curvature is needed
// (the modes' accelerations come from their equations), so only those carry it.
template <std::size_t N, std::size_t NM, std::size_t NC, std::size_t NO>
VIADUCT_ALWAYS_INLINE void kernel_body(const KernelInput& in, double* q_out, double* qd_out, double* ma_out, double* md_out,
                                       double* mn_out, SumStateT<N>& sums) {
  using L = Lanes<N>;
  constexpr bool fixed = NM && NC && NO;
  const std::size_t nm = NM ? NM : in.nm, nc = NC ? NC : in.nc, no = NO ? NO : in.no;
  const bool flex = NC ? (NC > NM) : in.flex;
  const std::size_t nr = flex ? no : 0;  // residual channels used (the stations')
  constexpr std::size_t cm = NM ? NM : 1, cc = NC ? NC : 1, co = NO ? NO : 1;
  const L zero = {}, one = zero + 1.0;
  L q_f[cm], qd_f[cm], pp_f[cm], am_f[cm], f_f[cc], d1_f[cc], d2_f[cc], d3_f[cc], c_f[co], dc_f[co], ma_f[co], md_f[co],
      mn_f[co], dj_f[co], aj_f[co];
  L *q = q_f, *qd = qd_f, *pp = pp_f, *am = am_f, *f = f_f, *d1 = d1_f, *d2 = d2_f, *d3 = d3_f, *c = c_f, *dc = dc_f,
        *ma = ma_f, *md = md_f, *mn = mn_f, *dj = dj_f, *aj = aj_f;
  std::vector<double> dyn;
  if constexpr (!fixed) {
    dyn.assign((4 * nm + 4 * nc + 7 * no + 1) * N, 0.0);
    L* at = align_lanes<L>(dyn.data());  // one spare group at the end
    for (L** a : {&q, &qd, &pp, &am}) *a = at, at += nm;
    for (L** a : {&f, &d1, &d2, &d3}) *a = at, at += nc;
    for (L** a : {&c, &dc, &ma, &md, &mn, &dj, &aj}) *a = at, at += no;
  }
  for (std::size_t i = 0; i < nm; ++i) q[i] = qd[i] = pp[i] = am[i] = zero;
  for (std::size_t ch = 0; ch < nc; ++ch) f[ch] = d1[ch] = d2[ch] = d3[ch] = zero;
  for (std::size_t j = 0; j < no; ++j) c[j] = dc[j] = ma[j] = md[j] = mn[j] = zero;

  L v = zero, n_steps = zero;
  lane_speeds<N>(in, v, n_steps);
  LoadCursorT<N> cur;
  cur.bind(in, nc, nm, nr, f, d1, d2, d3, c, dc, sums.pt);
  const double half_dt = 0.5 * in.dt;
  const Index min_steps = *std::min_element(in.n_steps, in.n_steps + N);
  // The residual channels the outputs read, [nm, nm + nr), advance in outputs_pass, after their
  // step's outputs (the sums read the outputs' values it keeps); the extra channels [nc − n_extra, nc)
  // with the modes' in LoadCursor::advance. Those in between (outputs beyond `no`, e.g. rails)
  // are read by nothing: they are set at each piece and not advanced.
  const bool has_sums = !fixed && in.n_sums;
  const std::size_t x1 = nc, x0 = fixed ? nc : nc - in.n_extra;
  // The outputs whose values the sums read, [k0, k1): only theirs are kept in dj (a store less a
  // step for every other output).
  std::size_t k0 = no, k1 = 0;
  for (std::size_t s = 0; has_sums && s < in.n_sums; ++s)
    if (in.sums[s].disp >= 0) {
      const auto jd = static_cast<std::size_t>(in.sums[s].disp);
      k0 = std::min(k0, jd), k1 = std::max(k1, jd + 1);
    }
  if (k1 <= k0) k0 = k1 = no;
  // The outputs before and after the sums' run a block of steps at a time (BlockOutputs) when
  // they are N or more; the load cursor then sets at each piece only the channels read step by step.
  BlockOutputs<N, NM> blk;
  bool blk_a = false, blk_b = false;
  if (!fixed && nm <= BlockOutputs<N, NM>::kMaxModes) {
    blk_a = blk.take(0, k0), blk_b = blk.take(k1, no);
    if (blk.n_ranges) {
      blk.bind(in, nm, no, flex);
      // (without residual channels, flex false, the extra channels follow the modes')
      const std::size_t r[4][2] = {{0, flex ? nm + (blk_a ? 0 : k0) : nm},
                                   {flex ? nm + k0 : 0, flex ? nm + k1 : 0},
                                   {flex ? nm + (blk_b ? no : k1) : 0, flex ? nm + no : 0},
                                   {x0, x1}};
      cur.keep(r);
    }
  }
  auto emit = [&](Index k) __attribute__((always_inline)) {
    const L live = static_cast<double>(k) <= n_steps ? one : zero;
    L *fr = f + nm, *r1 = d1 + nm, *r2 = d2 + nm, *r3 = d3 + nm;
    if (!blk_a) outputs_range<N, NM, false>(flex, nm, 0, k0, in.S, q, dj, fr, r1, r2, r3, md, mn, live);
    outputs_range<N, NM, true>(flex, nm, k0, k1, in.S, q, dj, fr, r1, r2, r3, md, mn, live);
    if (!blk_b) outputs_range<N, NM, false>(flex, nm, k1, no, in.S, q, dj, fr, r1, r2, r3, md, mn, live);
    emit_accelerations<N>(no, flex, aj, c, ma, in.hist, in.stride, in.nh, in.n_steps, k, live, k <= min_steps,
                       fixed ? nullptr : in.acc_idx, in.n_acc);
    if (has_sums) emit_sums<N>(in.sums, in.n_sums, flex, dj, aj, fr, c, f + in.extra0, half_dt, k, live, sums, true);
  };
  cur.start(in.v, in.dt, in.x_start);
  for (std::size_t j = 0; j < no; ++j) {  // from rest: q = 0, q̈ = p
    dj[j] = aj[j] = zero;
    for (std::size_t i = 0; i < nm; ++i) aj[j] += in.S[j * nm + i] * f[i];
  }
  emit(0);
  const L x_start = zero + in.x_start;
  blk.record(0, q, cur.ip, x_start);
  for (Index k = 1; k <= in.n_max; ++k) {
    check_cancel(k);  // the Python package's Ctrl-C
    for (std::size_t i = 0; i < nm; ++i) pp[i] = f[i];
    const L X = x_start + v * (static_cast<double>(k) * in.dt);
    cur.advance(nm, nr, X, fixed ? nullptr : in.acc_idx, in.n_acc, x0, x1);
    for (std::size_t i = 0; i < nm; ++i) {
      const double* cf = in.c8 + 8 * i;
      const L q0 = q[i], v0 = qd[i], p0 = pp[i], p1 = f[i];
      const L q1 = cf[0] * q0 + cf[1] * v0 + cf[2] * p0 + cf[3] * p1;
      const L v1 = cf[4] * q0 + cf[5] * v0 + cf[6] * p0 + cf[7] * p1;
      am[i] = p1 - in.two_zw[i] * v1 - in.w2[i] * q1;
      q[i] = q1;
      qd[i] = v1;
    }
    // Accelerations of the outputs in acc_idx only, when given (the others' are not read); the
    // deflection-type outputs in emit's outputs_pass.
    const std::size_t n_a = (fixed || !in.acc_idx) ? no : in.n_acc;
    for (std::size_t a = 0; a < n_a; ++a) {
      const std::size_t j = (fixed || !in.acc_idx) ? a : in.acc_idx[a];
      const double* sj = in.S + j * nm;
      L acc = zero;
      for (std::size_t i = 0; i < nm; ++i) acc += sj[i] * am[i];
      aj[j] = acc;
    }
    emit(k);
    blk.record(k, q, cur.ip, X);
    blk.flush(in.n_steps, false);
  }
  blk.flush(in.n_steps, true);
  for (std::size_t l = 0; l < N; ++l) {
    for (std::size_t i = 0; i < nm; ++i) q_out[i * N + l] = q[i][l], qd_out[i * N + l] = qd[i][l];
    for (std::size_t j = 0; j < no; ++j)
      ma_out[j * N + l] = ma[j][l], md_out[j * N + l] = md[j][l], mn_out[j * N + l] = mn[j][l];
  }
  blk.finish(md_out, mn_out);
}

// The same loop built twice on x86-64: for the baseline ISA and for AVX2 (one instruction per
// four-lane operation instead of two), chosen at run time by what the processor supports; and the
// general loops (not the fixed small ones, whose build would double) on eight lanes for AVX-512.
#ifdef VIADUCT_HAVE_AVX2_VARIANT
template <std::size_t NM, std::size_t NC, std::size_t NO>
VIADUCT_TARGET_AVX2 void kernel_avx2(const KernelInput& in, double* q, double* qd, double* ma, double* md, double* mn,
                                     SumState& su) {
  kernel_body<kLanes, NM, NC, NO>(in, q, qd, ma, md, mn, su);
}
template <std::size_t NM>
VIADUCT_TARGET_AVX512 void kernel_avx512(const KernelInput& in, double* q, double* qd, double* ma, double* md,
                                         double* mn, SumStateT<kWideLanes>& su) {
  kernel_body<kWideLanes, NM, 0, 0>(in, q, qd, ma, md, mn, su);
}
#endif

template <std::size_t NM, std::size_t NC, std::size_t NO>
void kernel(const KernelInput& in, double* q, double* qd, double* ma, double* md, double* mn, SumState& su) {
#ifdef VIADUCT_HAVE_AVX2_VARIANT
  if (cpu_has_avx2()) return kernel_avx2<NM, NC, NO>(in, q, qd, ma, md, mn, su);
#endif
  kernel_body<kLanes, NM, NC, NO>(in, q, qd, ma, md, mn, su);
}

// The bases the unrolled loops take (dispatch_fixed): up to 6 modes with 1–2 stations, no sums,
// every output's acceleration, the channels the modes' (and the stations' residuals).
bool fixed_kernel(const KernelInput& in) {
  return in.nm >= 1 && in.nm <= 6 && (in.no == 1 || in.no == 2) && !in.n_sums && !in.acc_idx &&
         in.nc == in.nm + (in.flex ? in.no : 0);
}

template <std::size_t NM, std::size_t NO>
bool dispatch_fixed(const KernelInput& in, double* q, double* qd, double* ma, double* md, double* mn, SumState& su) {
  if (in.nm != NM || in.no != NO || in.n_sums || in.acc_idx) return false;
  if (in.flex && in.nc == NM + NO) kernel<NM, NM + NO, NO>(in, q, qd, ma, md, mn, su);
  else if (!in.flex && in.nc == NM) kernel<NM, NM, NO>(in, q, qd, ma, md, mn, su);
  else return false;
  return true;
}

template <std::size_t... I>
bool dispatch_modes(std::index_sequence<I...>, const KernelInput& in, double* q, double* qd, double* ma, double* md,
                    double* mn, SumState& su) {
  return ((dispatch_fixed<I + 1, 1>(in, q, qd, ma, md, mn, su) || dispatch_fixed<I + 1, 2>(in, q, qd, ma, md, mn, su)) || ...);
}

template <std::size_t... I>
bool dispatch_general(std::index_sequence<I...>, const KernelInput& in, double* q, double* qd, double* ma, double* md,
                      double* mn, SumState& su) {
  return ((in.nm == I + 1 ? (kernel<I + 1, 0, 0>(in, q, qd, ma, md, mn, su), true) : false) || ...);
}

// Bases of up to 6 modes with 1–2 stations (no sums, every output's acceleration) get the
// unrolled loops; other outputs of up to 6 modes the general loop with the modes' count fixed
// (each output's sum over the modes unrolled); larger bases the general one.
void dispatch(const KernelInput& in, double* q, double* qd, double* ma, double* md, double* mn, SumState& su) {
  if (dispatch_modes(std::make_index_sequence<6>{}, in, q, qd, ma, md, mn, su)) return;
  if (dispatch_general(std::make_index_sequence<6>{}, in, q, qd, ma, md, mn, su)) return;
  kernel<0, 0, 0>(in, q, qd, ma, md, mn, su);
}

#ifdef VIADUCT_HAVE_AVX2_VARIANT
template <std::size_t... I>
bool dispatch_wide_modes(std::index_sequence<I...>, const KernelInput& in, double* q, double* qd, double* ma,
                         double* md, double* mn, SumStateT<kWideLanes>& su) {
  return ((in.nm == I + 1 ? (kernel_avx512<I + 1>(in, q, qd, ma, md, mn, su), true) : false) || ...);
}
#endif

// Eight lanes (called only when cpu_has_avx512() and !fixed_kernel(in)): the general loops, the
// modes' count fixed up to 6 as dispatch_general's.
void dispatch_wide(const KernelInput& in, double* q, double* qd, double* ma, double* md, double* mn,
                   SumStateT<kWideLanes>& su) {
#ifdef VIADUCT_HAVE_AVX2_VARIANT
  if (dispatch_wide_modes(std::make_index_sequence<6>{}, in, q, qd, ma, md, mn, su)) return;
  kernel_avx512<0>(in, q, qd, ma, md, mn, su);
#else
  kernel_body<kWideLanes, 0, 0, 0>(in, q, qd, ma, md, mn, su);
#endif
}

// Complex modes (damping that couples the modes): per coordinate k, y ← E y + α u₀ + β u₁ with
// u = p[c] + i p[c+1] (p[c] alone for a real coordinate), in split real arithmetic; the same
// folded loads and lanes as kernel_body, each channel evaluated afresh every step (DirectCursor).
struct ComplexInput {
  std::size_t nk = 0, nch = 0, nc = 0, no = 0;  // coordinates, load channels, all channels, stations
  bool flex = false;
  const double* co = nullptr;    // per coordinate: Er, Ei, αr, αi, βr, βi
  const std::size_t* ch = nullptr;
  const unsigned char* pair = nullptr;
  // Per output, per coordinate: the deflection's Dr, Di (disp_rows) and the acceleration's Lr, Li
  // (= Re, Im of acc·λ), Ar, Ai (acc_rows): apart, so the deflections' sums read only theirs.
  const double* disp_rows = nullptr;
  const double* acc_rows = nullptr;
  const double *breaks = nullptr, *coef = nullptr;
  std::size_t n_pieces = 0;
  double x_start = 0.0, dt = 0.0;
  double v[kWideLanes];        // [m/s] per lane (the first N of a kernel of N lanes)
  Index n_steps[kWideLanes];   // per lane
  Index n_max = 0;
  double* hist = nullptr;
  std::size_t stride = 0, nh = 0;
  const std::size_t* acc_idx = nullptr;  // the outputs whose acceleration is computed (null: all)
  std::size_t n_acc = 0;
  const OutputSum* sums = nullptr;  // as KernelInput's
  std::size_t n_sums = 0, extra0 = 0, n_extra = 0;
  const double* point = nullptr;
};

// Outputs [0, n) in blocks for f(std::integral_constant<size, B>, first): blocks of four; a
// remainder of one or two joins the last block (5 or 6: one block of B sums costs about B cycles a
// coordinate while B ≥ 3, the latency of one addition, so 4 + 1 padded to 4 + 4 cost 8 where 5
// costs 5), a remainder of three is a block of its own.
template <class F>
VIADUCT_ALWAYS_INLINE void out_blocks(std::size_t n, F&& f) {
  const std::size_t rem = n % 4, n4 = n < 4 ? 0 : (rem == 1 || rem == 2 ? n - rem - 4 : n - rem);
  std::size_t j = 0;
  for (; j < n4; j += 4) f(std::integral_constant<std::size_t, 4>{}, j);
  switch (n - j) {
    case 1: f(std::integral_constant<std::size_t, 1>{}, j); break;
    case 2: f(std::integral_constant<std::size_t, 2>{}, j); break;
    case 3: f(std::integral_constant<std::size_t, 3>{}, j); break;
    case 5: f(std::integral_constant<std::size_t, 5>{}, j); break;
    case 6: f(std::integral_constant<std::size_t, 6>{}, j); break;
    default: break;  // 0
  }
}

// Outputs [j0, j0 + B): each deflection-type value Re Σₖ (Dr + i Di)(yr + i yi), summed over the
// coordinates in order from zero, into dj.
template <std::size_t N, std::size_t B>
VIADUCT_ALWAYS_INLINE void disp_block(const double* rows, std::size_t nk, std::size_t j0, const Lanes<N>* yr,
                                      const Lanes<N>* yi, Lanes<N>* dj) {
  using L = Lanes<N>;
  const double* r[B];
  L s[B];
  for (std::size_t u = 0; u < B; ++u) r[u] = rows + 2 * (j0 + u) * nk, s[u] = L{};
  for (std::size_t k = 0; k < nk; ++k) {
    const L a = yr[k], b = yi[k];
    for (std::size_t u = 0; u < B; ++u) s[u] += r[u][2 * k] * a - r[u][2 * k + 1] * b;
  }
  for (std::size_t u = 0; u < B; ++u) dj[j0 + u] = s[u];
}

// The accelerations of outputs idx[n0 … n0 + B) (idx null: n0 … n0 + B), each Re Σₖ of the
// coordinate's share (Lr + i Li)(yr + i yi) and its input's (Ar + i Ai)(u1r + i u1i), u1r =
// f[ir[k]] and u1i = f[ii[k]], into aj.
template <std::size_t N, std::size_t B>
VIADUCT_ALWAYS_INLINE void acc_block(const double* rows, std::size_t nk, std::size_t n0, const std::size_t* idx,
                                     const Lanes<N>* yr, const Lanes<N>* yi, const Lanes<N>* f, const std::size_t* ir,
                                     const std::size_t* ii, Lanes<N>* aj) {
  using L = Lanes<N>;
  std::size_t j[B];
  const double* q[B];
  L s[B];
  for (std::size_t u = 0; u < B; ++u) j[u] = idx ? idx[n0 + u] : n0 + u, q[u] = rows + 4 * j[u] * nk, s[u] = L{};
  for (std::size_t k = 0; k < nk; ++k) {
    const L a = yr[k], b = yi[k], c0 = f[ir[k]], c1 = f[ii[k]];
    const std::size_t o = 4 * k;
    for (std::size_t u = 0; u < B; ++u) s[u] += q[u][o] * a - q[u][o + 1] * b + q[u][o + 2] * c0 - q[u][o + 3] * c1;
  }
  for (std::size_t u = 0; u < B; ++u) aj[j[u]] = s[u];
}

// N cases at once.
template <std::size_t N>
VIADUCT_ALWAYS_INLINE void complex_body(const ComplexInput& in, double* state_out, double* ma_out, double* md_out,
                                        double* mn_out, SumStateT<N>& sums) {
  using L = Lanes<N>;
  const std::size_t nk = in.nk, nch = in.nch, nc = in.nc, no = in.no, nr = in.flex ? no : 0;
  const L zero = {}, one = zero + 1.0;
  const std::size_t ncp = (nc + N - 1) / N * N;  // the channels' values, rounded up to whole blocks
  std::vector<double> buf((2 * nk + 2 * (ncp + 1) + 6 * no + 1) * N, 0.0);
  L* at = align_lanes<L>(buf.data());
  // y; the channels' values across the lanes at the step's start (f0) and end (f: DirectCursor::
  // values), each followed by a zero (f[ncp]); c the residuals' curvatures. Coordinate k's input
  // u = f[ir[k]] + i f[ii[k]]: p[c] + i p[c+1], or p[c] and the zero for a real coordinate.
  L *yr = at, *yi = yr + nk, *f0 = yi + nk, *f = f0 + ncp + 1, *c = f + ncp + 1, *ma = c + no, *md = ma + no,
    *mn = md + no, *dj = mn + no, *aj = dj + no;
  std::vector<std::size_t> ir(nk), ii(nk);
  for (std::size_t k = 0; k < nk; ++k) ir[k] = in.ch[k], ii[k] = in.pair[k] ? in.ch[k] + 1 : ncp;
  L v = zero, n_steps = zero;
  lane_speeds<N>(in, v, n_steps);
  DirectCursor<N> cur;
  cur.bind(in, nc, nch, nr, c, sums.pt);
  const double half_dt = 0.5 * in.dt;
  const Index min_steps = *std::min_element(in.n_steps, in.n_steps + N);
  auto emit = [&](Index k) {
    const L live = static_cast<double>(k) <= n_steps ? one : zero;
    emit_stations<N>(no, in.flex, dj, aj, f + nch, c, md, mn, ma, in.hist, in.stride, in.nh, in.n_steps, k, live,
                  k <= min_steps, in.acc_idx, in.n_acc);
    if (in.n_sums) emit_sums<N>(in.sums, in.n_sums, in.flex, dj, aj, f + nch, c, f + in.extra0, half_dt, k, live, sums);
  };
  // The coordinates' outputs for the current y and the inputs u1 (every output: the first sample).
  auto outputs = [&]() {
    for (std::size_t j = 0; j < no; ++j) dj[j] = aj[j] = zero;
    for (std::size_t k = 0; k < nk; ++k) {
      const L a = yr[k], b = yi[k];
      for (std::size_t j = 0; j < no; ++j) {
        const double* r = in.disp_rows + 2 * (j * nk + k);
        const double* q = in.acc_rows + 4 * (j * nk + k);
        dj[j] += r[0] * a - r[1] * b;
        aj[j] += q[0] * a - q[1] * b + q[2] * f[ir[k]] - q[3] * f[ii[k]];
      }
    }
  };
  const L x_start = zero + in.x_start;
  cur.start(in.v, in.x_start);
  cur.values(x_start, f);
  outputs();
  emit(0);
  for (Index step = 1; step <= in.n_max; ++step) {
    check_cancel(step);  // the Python package's Ctrl-C
    std::swap(f0, f);  // the last step's end is this step's start
    const L X = x_start + v * (static_cast<double>(step) * in.dt);
    cur.advance(X);
    cur.values(X, f);
    for (std::size_t k = 0; k < nk; ++k) {
      const double* e = in.co + 6 * k;
      const L a = yr[k], b = yi[k], u0r = f0[ir[k]], u0i = f0[ii[k]], u1r = f[ir[k]], u1i = f[ii[k]];
      const L nr_ = e[0] * a - e[1] * b + e[2] * u0r - e[3] * u0i + e[4] * u1r - e[5] * u1i;
      const L ni_ = e[0] * b + e[1] * a + e[2] * u0i + e[3] * u0r + e[4] * u1i + e[5] * u1r;
      yr[k] = nr_;
      yi[k] = ni_;
    }
    // Output by output over the coordinates (a station's rows contiguous, the sum in a register),
    // in the coordinates' order as before: the same sums. Several outputs at a time, each its own
    // sum in its own register (one sum's additions wait on each other, several sums' do not):
    // blocks of four, the last of 3, 5 or 6 so that no output is computed twice (out_blocks).
    out_blocks(no, [&](auto B, std::size_t j0) __attribute__((always_inline)) {
      disp_block<N, decltype(B)::value>(in.disp_rows, nk, j0, yr, yi, dj);
    });
    // The accelerations of the outputs in acc_idx only, when given (the others' are not read),
    // likewise in blocks.
    const std::size_t n_a = in.acc_idx ? in.n_acc : no;
    out_blocks(n_a, [&](auto B, std::size_t n0) __attribute__((always_inline)) {
      acc_block<N, decltype(B)::value>(in.acc_rows, nk, n0, in.acc_idx, yr, yi, f, ir.data(), ii.data(), aj);
    });
    emit(step);
  }
  for (std::size_t l = 0; l < N; ++l) {
    double st = 0.0;
    for (std::size_t k = 0; k < nk; ++k) st += yr[k][l] + yi[k][l];
    state_out[l] = st;
    for (std::size_t j = 0; j < no; ++j)
      ma_out[j * N + l] = ma[j][l], md_out[j * N + l] = md[j][l], mn_out[j * N + l] = mn[j][l];
  }
}

#ifdef VIADUCT_HAVE_AVX2_VARIANT
VIADUCT_TARGET_AVX2 void complex_avx2(const ComplexInput& in, double* st, double* ma, double* md, double* mn,
                                      SumState& su) {
  complex_body(in, st, ma, md, mn, su);
}
// Eight cases a pass: one AVX-512 operation where AVX2 needs two for four (the same numbers).
VIADUCT_TARGET_AVX512 void complex_avx512(const ComplexInput& in, double* st, double* ma, double* md, double* mn,
                                          SumStateT<kWideLanes>& su) {
  complex_body(in, st, ma, md, mn, su);
}
#endif

void complex_kernel(const ComplexInput& in, double* st, double* ma, double* md, double* mn, SumState& su) {
#ifdef VIADUCT_HAVE_AVX2_VARIANT
  if (cpu_has_avx2()) return complex_avx2(in, st, ma, md, mn, su);
#endif
  complex_body(in, st, ma, md, mn, su);
}

// Called only when cpu_has_avx512() (the driver takes eight lanes only then).
void complex_kernel(const ComplexInput& in, double* st, double* ma, double* md, double* mn, SumStateT<kWideLanes>& su) {
#ifdef VIADUCT_HAVE_AVX2_VARIANT
  complex_avx512(in, st, ma, md, mn, su);
#else
  complex_body(in, st, ma, md, mn, su);
#endif
}

}  // namespace

namespace {

// The kernel inputs of one reduction and one set of folded loads, with the arrays they point
// into: the exact step of each damped oscillator (classical modes), or of each complex
// coordinate with the output rows split into parts (complex modes).
struct PeaksSetup {
  bool complex = false;
  std::vector<double> c8, two_zw, w2;  // classical
  KernelInput in;
  std::vector<double> co, disp_rows, acc_rows;  // complex
  std::vector<std::size_t> chan;
  std::vector<unsigned char> pair;
  ComplexInput ci;
};

void prepare_classical(const ModalReduction& r, const MovingChannels& L, double dt, std::size_t no, PeaksSetup& k) {
  const std::size_t nm = L.n_modes;
  k.c8.resize(8 * nm), k.two_zw.resize(nm), k.w2.resize(nm);
  for (std::size_t i = 0; i < nm; ++i) {
    const double om = r.omega()[static_cast<Index>(i)], ze = r.zeta()[static_cast<Index>(i)];
    const auto cf = exact_step_coefficients(om, ze, dt);
    std::copy(cf.begin(), cf.end(), k.c8.begin() + static_cast<std::ptrdiff_t>(8 * i));
    k.two_zw[i] = 2.0 * ze * om;
    k.w2[i] = om * om;
  }
  KernelInput& in = k.in;
  in.c8 = k.c8.data();
  in.two_zw = k.two_zw.data();
  in.w2 = k.w2.data();
  in.S = r.output_rows().data();
  in.breaks = L.breaks.data();
  in.coef = L.coef.data();
  in.n_pieces = L.breaks.size() - 1;
  in.x_start = L.x_start;
  in.dt = dt;
  in.nm = nm;
  in.nc = L.n_channels;
  in.no = no;
  in.flex = L.n_outputs > 0;
}

void prepare_complex(const ModalReduction& r, const MovingChannels& L, double dt, std::size_t no, PeaksSetup& k) {
  using cd = std::complex<double>;
  const ModalReduction::ComplexForm cf = r.complex_form();
  const std::size_t nk = cf.lambda.size();
  k.co.resize(6 * nk);
  k.chan.resize(nk);
  k.pair.resize(nk);
  for (std::size_t c = 0; c < nk; ++c) {
    const auto [e, al, be] = complex_step_coefficients(cf.lambda[c], dt);  // y₁ = E y₀ + α u₀ + β u₁
    const double v6[6] = {e.real(), e.imag(), al.real(), al.imag(), be.real(), be.imag()};
    std::copy(v6, v6 + 6, k.co.begin() + static_cast<std::ptrdiff_t>(6 * c));
    k.chan[c] = static_cast<std::size_t>(cf.channel[c]);
    k.pair[c] = cf.pair[c] ? 1 : 0;
  }
  k.disp_rows.resize(2 * no * nk);
  k.acc_rows.resize(4 * no * nk);
  for (std::size_t j = 0; j < no; ++j)
    for (std::size_t c = 0; c < nk; ++c) {
      const auto jj = static_cast<Index>(j), kk = static_cast<Index>(c);
      const cd d = cf.disp(jj, kk), a = cf.acc(jj, kk), al = a * cf.lambda[c];
      const double d2[2] = {d.real(), d.imag()}, a4[4] = {al.real(), al.imag(), a.real(), a.imag()};
      std::copy(d2, d2 + 2, k.disp_rows.begin() + static_cast<std::ptrdiff_t>(2 * (j * nk + c)));
      std::copy(a4, a4 + 4, k.acc_rows.begin() + static_cast<std::ptrdiff_t>(4 * (j * nk + c)));
    }
  ComplexInput& ci = k.ci;
  ci.nk = nk;
  ci.nch = L.n_modes;
  ci.nc = L.n_channels;
  ci.no = no;
  ci.flex = L.n_outputs > 0;
  ci.co = k.co.data();
  ci.ch = k.chan.data();
  ci.pair = k.pair.data();
  ci.disp_rows = k.disp_rows.data();
  ci.acc_rows = k.acc_rows.data();
  ci.breaks = L.breaks.data();
  ci.coef = L.coef.data();
  ci.n_pieces = L.breaks.size() - 1;
  ci.x_start = L.x_start;
  ci.dt = dt;
}

// Peaks (and the acceleration histories when recorded) of lane l after a kernel run; SolverError
// when the lane's state or outputs are not finite.
// The outputs' maxima of lane l at j·n_run + l (n_run lanes a run).
PeaksCaseResult lane_result(std::size_t l, std::size_t n_run, std::size_t no, const std::vector<double>& ma,
                            const std::vector<double>& md, const std::vector<double>& mn, double state,
                            const double* hist, std::size_t nh, std::size_t stride, Index n_steps, double speed) {
  // A non-finite state stays so (the recurrence is linear), and std::max would skip a NaN.
  PeaksCaseResult res;
  res.max_abs_disp.resize(static_cast<Index>(no));
  res.max_disp.resize(static_cast<Index>(no));
  res.min_disp.resize(static_cast<Index>(no));
  res.max_abs_acc.resize(static_cast<Index>(no));
  if (hist) res.acc.resize(n_steps + 1, static_cast<Index>(nh));
  bool finite = std::isfinite(state);
  for (std::size_t j = 0; j < no; ++j) {
    const auto jj = static_cast<Index>(j);
    res.max_disp[jj] = md[j * n_run + l];
    res.min_disp[jj] = -mn[j * n_run + l];
    res.max_abs_disp[jj] = std::max(md[j * n_run + l], mn[j * n_run + l]);
    res.max_abs_acc[jj] = ma[j * n_run + l];
    finite = finite && std::isfinite(md[j * n_run + l]) && std::isfinite(mn[j * n_run + l]);
    if (hist && j < nh) {
      res.acc.col(jj) = Eigen::Map<const Vector>(hist + (l * nh + j) * stride, n_steps + 1);
      finite = finite && res.acc.col(jj).allFinite();
    } else {
      finite = finite && std::isfinite(ma[j * n_run + l]);
    }
  }
  if (!finite)
    throw SolverError("modal superposition: the state became non-finite (speed " + format_number(speed, 6) + " m/s)");
  return res;
}

// The sums' extremes of lane l; SolverError when one is not finite.
template <std::size_t N>
void take_sums(const SumStateT<N>& su, std::size_t n_sums, std::size_t l, double speed, PeaksCaseResult& res) {
  if (!n_sums) return;
  res.max_sum.resize(static_cast<Index>(n_sums));
  res.min_sum.resize(static_cast<Index>(n_sums));
  for (std::size_t s = 0; s < n_sums; ++s) {
    const double hi = su.hi[s][l], lo = su.lo[s][l];
    if (!std::isfinite(hi) || !std::isfinite(lo))
      throw SolverError("modal superposition: a sum of outputs became non-finite (speed " + format_number(speed, 6) + " m/s)");
    res.max_sum[static_cast<Index>(s)] = hi;
    res.min_sum[static_cast<Index>(s)] = lo;
  }
}

void check_peaks_input(const ModalReduction& r, const MovingChannels& L, const std::vector<PeaksCase>& cases, double dt,
                       std::size_t n_outputs, const std::vector<OutputSum>& sums) {
  for (const PeaksCase& c : cases) {
    require_positive(c.speed, "speed [m/s]");
    require_valid(TimeGrid{dt, c.t_end}, "modal superposition");
  }
  if (L.n_modes != static_cast<std::size_t>(r.n_channels()) ||
      (L.n_outputs != 0 && L.n_outputs != static_cast<std::size_t>(r.n_outputs())) ||
      L.n_channels != L.n_modes + L.n_outputs + L.n_extra || L.breaks.size() < 2 ||
      L.coef.size() != L.breaks.size() * 4 * L.n_channels || (L.n_extra && L.point.size() != L.breaks.size() * L.n_extra))
    throw InputError("the folded loads do not belong to this modal model");
  if (n_outputs < 1 || n_outputs > static_cast<std::size_t>(r.n_outputs()))
    throw InputError("the modal model lacks the outputs asked for");
  const auto n_out = static_cast<Index>(n_outputs);
  auto out_ok = [&](Index j) { return j >= -1 && j < n_out; };
  for (const OutputSum& o : sums)
    if (!out_ok(o.disp) || !out_ok(o.acc) || !out_ok(o.acc_integral) || o.load_channel < -1 ||
        o.load_channel >= static_cast<Index>(L.n_extra))
      throw InputError("a sum of outputs names an output or load channel the modal model does not record");
}

// One batch's N lanes (speeds, step counts) and history buffer into a kernel's input (a
// KernelInput or a ComplexInput).
template <class Input, std::size_t N>
void set_batch(Input& in, const double (&v)[N], const Index (&n_steps)[N], Index n_max, double* hist, std::size_t nh,
               std::size_t stride) {
  std::copy(v, v + N, in.v);
  std::copy(n_steps, n_steps + N, in.n_steps);
  in.n_max = n_max;
  in.hist = hist;
  in.nh = nh;
  in.stride = stride;
}

// The cases in batches of N (spare lanes repeat the last case), through the classical kernel
// (four lanes) or the complex one (four or eight), into `out` in the cases' order.
template <std::size_t N>
void run_batches(PeaksSetup& k, const ModalReduction& r, const MovingChannels& L, const std::vector<PeaksCase>& cases,
                 double dt, std::size_t no, std::size_t nh, const std::vector<char>& has_acc, bool record_acc,
                 double max_history_bytes, std::vector<PeaksCaseResult>& out) {
  const std::size_t nm = L.n_modes, n_sums = k.in.n_sums;
  // The acceleration histories of a batch: not zeroed (the kernel writes every value lane_result
  // reads: lane l's steps 0 … n_steps[l] of each output), so a sweep's calls, one per block of
  // speeds, do not fill and fault in a new buffer each (4 % of Old Guadiana's assessment when they
  // did); large ones are given again within the sweep (BlockReuse), small ones by malloc.
  std::vector<double, UninitAllocator<double>> hist_buf;
  double* hist = nullptr;
  std::vector<double> q(nm * N), qd(nm * N), ma(no * N), md(no * N), mn(no * N), state(N);
  for (std::size_t first = 0; first < cases.size(); first += N) {
    const auto wall0 = std::chrono::steady_clock::now();
    const std::size_t n_lanes = std::min(N, cases.size() - first);
    double v[N];
    Index n_steps[N], n_max = 0;
    for (std::size_t l = 0; l < N; ++l) {
      // Spare lanes repeat the last case; their results are dropped.
      const PeaksCase& c = cases[first + std::min(l, n_lanes - 1)];
      v[l] = c.speed;
      n_steps[l] = TimeGrid{dt, c.t_end}.n_steps();
      n_max = std::max(n_max, n_steps[l]);
    }
    const std::size_t stride = static_cast<std::size_t>(n_max) + 1;
    if (record_acc) {
      if (static_cast<double>(N * nh * stride) * sizeof(double) > max_history_bytes)
        throw InputError("the station histories of " + std::to_string(N) +
                         " speeds would not fit in memory: raise analysis.dt");
      const std::size_t n_hist = std::max<std::size_t>(N * nh * stride, 1);  // non-null: histories asked
      if (hist_buf.size() < n_hist) {
        hist_buf.clear();  // nothing to carry over into the larger block
        hist_buf.resize(n_hist);
      }
      hist = hist_buf.data();
    }
    SumStateT<N> su(n_sums, L.n_extra);
    if (!k.complex) {
      set_batch(k.in, v, n_steps, n_max, hist, nh, stride);
      if constexpr (N == kLanes) dispatch(k.in, q.data(), qd.data(), ma.data(), md.data(), mn.data(), su);
      else dispatch_wide(k.in, q.data(), qd.data(), ma.data(), md.data(), mn.data(), su);
      for (std::size_t l = 0; l < N; ++l) {
        state[l] = 0.0;
        for (std::size_t i = 0; i < nm; ++i) state[l] += q[i * N + l] + qd[i * N + l];
      }
    } else {
      set_batch(k.ci, v, n_steps, n_max, hist, nh, stride);
      complex_kernel(k.ci, state.data(), ma.data(), md.data(), mn.data(), su);
    }
    const double wall = detail::seconds_since(wall0);
    for (std::size_t l = 0; l < n_lanes; ++l) {
      PeaksCaseResult res =
          lane_result(l, N, no, ma, md, mn, state[l], hist, nh, stride, n_steps[l], v[l]);
      take_sums(su, n_sums, l, v[l], res);
      for (std::size_t j = 0; j < no; ++j)
        if (!has_acc[j]) res.max_abs_acc[static_cast<Index>(j)] = 0.0;
      res.summary = detail::fixed_step_summary(Kernel::modal_peaks, n_steps[l], dt, r.n_dofs(), r.n_modes(), 0,
                                               wall / static_cast<double>(n_lanes));
      out.push_back(std::move(res));
    }
  }
}

}  // namespace

namespace {

// The largest and smallest value of a[0] + a[1]·s + a[2]·s² + a[3]·s³ over 0 ≤ s ≤ len: the
// values at the ends and where the slope a[1] + 2a[2]·s + 3a[3]·s² is zero within (the roots in
// their stable form), each by Horner as the kernel evaluates. A root's rounding moves the value
// at it only to second order (the slope is zero there), and two roots too close for the
// discriminant's sign to be right hold a bump of the order of its rounding to the power 1.5: both
// far below the margin the caller adds.
void cubic_range(const double (&a)[4], double len, double& hi, double& lo) noexcept {
  bool nan = false;
  auto at = [&](double s) {
    const double v = a[0] + s * (a[1] + s * (a[2] + s * a[3]));
    nan = nan || std::isnan(v);
    return v;
  };
  const double v0 = at(0.0), v1 = at(len);
  hi = std::max(v0, v1), lo = std::min(v0, v1);
  auto take = [&](double s) {
    if (!(s > 0.0 && s < len)) return;
    const double v = at(s);
    hi = std::max(hi, v), lo = std::min(lo, v);
  };
  const double A = 3.0 * a[3], Bh = a[2], C = a[1];  // slope: A·s² + 2·Bh·s + C
  if (A != 0.0) {
    const double disc = Bh * Bh - A * C;
    if (disc >= 0.0) {
      const double q = -(Bh + std::copysign(std::sqrt(disc), Bh));
      take(q / A);
      if (q != 0.0) take(C / q);
    }
  } else if (Bh != 0.0) {
    take(-C / (2.0 * Bh));
  }
  if (nan) hi = lo = std::numeric_limits<double>::quiet_NaN();
}

// MovingChannels::residual_bounds of pieces [p0, p1) of L into b (bound_residuals).
void bound_pieces(const MovingChannels& L, std::size_t p0, std::size_t p1, double* b) noexcept {
  const std::size_t nc = L.n_channels, nm = L.n_modes, no = L.n_outputs;
  for (std::size_t p = p0; p < p1; ++p) {
    const double len = L.breaks[p + 1] - L.breaks[p], pw[4] = {1.0, len, len * len, len * len * len};
    const double* d = L.coef.data() + p * 4 * nc + nm;
    for (std::size_t j = 0; j < no; ++j) {
      const double a[4] = {d[j], d[nc + j], d[2 * nc + j], d[3 * nc + j]};
      double hi = a[0], lo = a[0], ab = std::abs(a[0]);
      for (std::size_t n = 1; n < 4; ++n) {
        const double t = a[n] * pw[n];
        hi += std::max(t, 0.0), lo += std::min(t, 0.0), ab += std::abs(t);
      }
      double rhi, rlo;
      cubic_range(a, len, rhi, rlo);
      // The cubic's range (its terms' bound: a third more blocks of the job of docs/benchmarks.md
      // were evaluated), or the terms' bound where the range is not a number (infinite
      // coefficients: min and max keep their first argument against NaN).
      const double m = 1e-10 * ab;
      b[(2 * p) * no + j] = std::min(hi + m, rhi + m);
      b[(2 * p + 1) * no + j] = std::max(lo - m, rlo - m);
    }
  }
}

}  // namespace

std::vector<PeaksCaseResult> modal_peaks(const ModalReduction& r, const MovingChannels& L,
                                         const std::vector<PeaksCase>& cases, double dt, std::size_t n_outputs,
                                         bool record_acc, double max_history_bytes,
                                         const std::vector<OutputSum>& sums, Index acc_outputs) {
  if (cases.empty()) return {};
  check_peaks_input(r, L, cases, dt, n_outputs, sums);
  // The recorded outputs are the reduction's first n_outputs (rails above deck stations may follow).
  const std::size_t no = n_outputs;
  // Acceleration histories of the first nh outputs (the stations a filter takes; not the effects).
  const std::size_t nh = !record_acc ? 0 : acc_outputs < 0 ? no : std::min(no, static_cast<std::size_t>(acc_outputs));
  PeaksSetup k;
  k.complex = r.complex_modes();
  if (!k.complex) prepare_classical(r, L, dt, no, k);
  else prepare_complex(r, L, dt, no, k);
  // The residuals' bounds over each piece, for the outputs a block of steps at a time
  // (BlockOutputs): the folded train's (study::fold_train computes them with the table), or here.
  std::vector<double> own;
  if (!k.complex && L.n_outputs) {
    const std::size_t np = L.breaks.size() - 1;
    k.in.rbound = L.residual_bounds.data();
    if (L.residual_bounds.size() != 2 * np * L.n_outputs) {
      own.resize(2 * np * L.n_outputs);
      bound_pieces(L, 0, np, own.data());
      k.in.rbound = own.data();
    }
    k.in.rb_stride = L.n_outputs;
  }
  const std::size_t n_sums = sums.size(), extra0 = L.n_modes + L.n_outputs;
  // Accelerations: of the first acc_outputs outputs and the sums' parts (the others' maxima 0).
  std::vector<std::size_t> acc_idx;
  std::vector<char> has_acc(no, acc_outputs < 0 ? 1 : 0);
  if (acc_outputs >= 0) {
    for (std::size_t j = 0; j < no && j < static_cast<std::size_t>(acc_outputs); ++j) has_acc[j] = 1;
    for (const OutputSum& o : sums)
      for (Index j : {o.acc, o.acc_integral})
        if (j >= 0) has_acc[static_cast<std::size_t>(j)] = 1;
    for (std::size_t j = 0; j < no; ++j)
      if (has_acc[j]) acc_idx.push_back(j);
    k.in.acc_idx = k.ci.acc_idx = acc_idx.data();
    k.in.n_acc = k.ci.n_acc = acc_idx.size();
  }
  k.in.sums = k.ci.sums = sums.data();
  k.in.n_sums = k.ci.n_sums = n_sums;
  k.in.extra0 = k.ci.extra0 = extra0;
  k.in.n_extra = k.ci.n_extra = L.n_extra;
  k.in.point = k.ci.point = L.n_extra ? L.point.data() : nullptr;
  // Eight cases a pass where the processor has AVX-512 (and eight cases' histories fit where they
  // are recorded), for complex modes and the classical general loops; else four (the classical
  // kernel's unrolled small bases too).
  Index most_steps = 0;
  for (const PeaksCase& c : cases) most_steps = std::max(most_steps, TimeGrid{dt, c.t_end}.n_steps());
  const double wide_bytes = static_cast<double>(kWideLanes * nh) * static_cast<double>(most_steps + 1) * sizeof(double);
  std::vector<PeaksCaseResult> out;
  if ((k.complex || !fixed_kernel(k.in)) && cpu_has_avx512() && (!record_acc || wide_bytes <= max_history_bytes))
    run_batches<kWideLanes>(k, r, L, cases, dt, no, nh, has_acc, record_acc, max_history_bytes, out);
  else
    run_batches<kLanes>(k, r, L, cases, dt, no, nh, has_acc, record_acc, max_history_bytes, out);
  return out;
}

}  // namespace viaduct::solve::detail

namespace viaduct::solve {

void bound_residuals(MovingChannels& L, std::size_t p0, std::size_t p1) noexcept {
  detail::bound_pieces(L, p0, p1, L.residual_bounds.data());
}

}  // namespace viaduct::solve
