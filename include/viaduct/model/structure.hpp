#pragma once
/// \file Bridge spans, ballasted track and their assembly into M a + C v + K u = f.
///
/// Coordinates: x [m] along the line, x = 0 at the start of the first span; spans follow each
/// other without gaps, as a chain of simply supported spans (each on its own two bearings) or as
/// one continuous deck over intermediate supports (BridgeParams::continuous). Deflections are positive downwards (the direction of axle loads).
/// A scenario builds only what it names: without TrackParams there are no track DOFs and loads
/// act on the deck directly.

#include <array>
#include <complex>
#include <optional>
#include <string>
#include <vector>

#include "viaduct/core/types.hpp"

namespace viaduct::model {

/// One Bernoulli–Euler span: simply supported, or one span of a continuous deck.
struct SpanParams {
  double length = 0.0;      ///< [m] > 0
  double EI = 0.0;          ///< [N·m²] bending stiffness, > 0
  double mass_per_m = 0.0;  ///< [kg/m] mass per length, > 0 (see BridgeParams::mass_includes_track)
};

/// Vertical bearing under each span end (the same for all span ends); on a continuous deck one
/// bearing per support, the intermediate ones shared by the two spans they carry.
struct BearingParams {
  bool rigid = true;  ///< true: deflection fixed at the bearing; false: spring k and dashpot c
  double k = 0.0;     ///< [N/m] vertical stiffness when not rigid, > 0
  double c = 0.0;     ///< [N·s/m] vertical damping when not rigid, >= 0
  /// [N·m/rad] rotational spring at each span end (integral or frame abutments, restrained
  /// ends), >= 0; 0: free to rotate (simply supported). A very large value clamps the end.
  /// On a continuous deck: at the deck's two ends only (the intermediate supports let it rotate).
  double rotational_k = 0.0;
};

enum class DampingKind {
  none,      ///< no structural damping of the bridge (track dashpots still act)
  modal,     ///< the same ratio for every mode of each span on its bearings (of the whole deck when continuous)
  rayleigh,  ///< C = a0 M + a1 K of the bridge, fitted to two (frequency, ratio) pairs
};

/// Structural damping of the bridge (deck beams and bearings; track dashpots are separate).
struct BridgeDamping {
  DampingKind kind = DampingKind::modal;
  double ratio = 0.0;   ///< [-] modal: ratio of critical for all span modes, in [0, 1)
  double f1_hz = 0.0;   ///< [Hz] rayleigh: first frequency, > 0
  double ratio1 = 0.0;  ///< [-] rayleigh: ratio at f1_hz, in [0, 1)
  double f2_hz = 0.0;   ///< [Hz] rayleigh: second frequency, > f1_hz
  double ratio2 = 0.0;  ///< [-] rayleigh: ratio at f2_hz, in [0, 1)
};

struct BridgeParams {
  std::vector<SpanParams> spans;   ///< at least one span, in order along x
  double element_size = 0.5;       ///< [m] target deck element length, > 0 (rounded per span)
  double added_mass_per_m = 0.0;   ///< [kg/m] non-structural mass on every span, >= 0
  /// true: mass_per_m already includes the track carried by the deck; when a track is modelled
  /// its mass per metre (rail + (sleeper + ballast)/spacing) is taken off the deck so that it is
  /// not counted twice. Ignored without track.
  bool mass_includes_track = false;
  /// true: the spans form one continuous deck over intermediate supports (nodes shared at the
  /// supports, one bearing per support); false: a chain of simply supported spans.
  bool continuous = false;
  BearingParams bearings;
  BridgeDamping damping;

  double total_length() const;  ///< [m] sum of span lengths
  /// False with a reason naming the violated constraint.
  bool is_valid(std::string* why) const;
};

/// Spring and dashpot in parallel.
struct SpringDashpot {
  double k = 0.0;  ///< [N/m] >= 0
  double c = 0.0;  ///< [N·s/m] >= 0
};

/// Three-layer discrete ballasted track (Zhai): rail beam on pads, sleepers, ballast masses
/// with shear coupling, subgrade. Values are per rail seat (per sleeper).
struct TrackParams {
  double rail_EI = 0.0;             ///< [N·m²] rail bending stiffness, > 0
  double rail_mass_per_m = 0.0;     ///< [kg/m] rail mass per length, > 0
  double sleeper_spacing = 0.6;     ///< [m] > 0
  double sleeper_mass = 0.0;        ///< [kg] per rail seat, > 0
  double ballast_mass = 0.0;        ///< [kg] per rail seat, > 0
  SpringDashpot pad;                ///< rail to sleeper
  SpringDashpot ballast;            ///< sleeper to ballast mass
  SpringDashpot shear;              ///< ballast mass to the next ballast mass
  SpringDashpot subgrade;           ///< ballast mass to ground, off the bridge
  SpringDashpot subgrade_on_bridge; ///< ballast mass to deck, on the bridge
  double approach_length = 20.0;    ///< [m] track before the bridge, >= 0
  /// [m] where the sleepers sit: the first on the bridge at this distance from its start, in
  /// [0, sleeper_spacing), the track then starting at the first sleeper at or before
  /// −approach_length; < 0 (unset): the track starts at −approach_length with a sleeper.
  double first_sleeper_offset = -1.0;
  double exit_length = 20.0;        ///< [m] track after the bridge, >= 0
  int rail_elements_per_bay = 1;    ///< rail elements between two sleepers, >= 1

  double mass_per_m() const;  ///< [kg/m] rail + (sleeper + ballast) / spacing
  double start_x() const;     ///< [m] x of the track's first sleeper (<= −approach_length)
  bool is_valid(std::string* why) const;
};

/// Linear interpolation of a beam's deflection at one point: w(x) = Σ N[i] u[dofs[i]].
/// A dof of -1 is a fixed (constrained) DOF and contributes nothing.
struct PointCoupling {
  std::array<Index, 4> dofs{{-1, -1, -1, -1}};
  std::array<double, 4> N{{0, 0, 0, 0}};
  double value(const Vector& u) const;
  std::complex<double> complex_value(const Eigen::VectorXcd& u) const;  ///< value() of a complex field
};

/// A linear form of the DOFs, y = Σ weight[k] · u[dof[k]] (fixed DOFs left out).
struct DofWeights {
  std::vector<Index> dof;
  std::vector<double> weight;
  double value(const Vector& u) const;
};

/// One beam element of the path the axles roll along (rail with track, deck without).
struct PathElement {
  double x0 = 0.0;  ///< [m] start
  double h = 0.0;   ///< [m] length
  std::array<Index, 4> dofs{{-1, -1, -1, -1}};  ///< w0, θ0, w1, θ1 (-1: fixed)
};

/// The force a bearing carries [N], compression positive (the deck pushing down on it), as
/// R = k·u + m·a + c·v + the consistent load at its fixed DOF. Elastic bearings: the spring and
/// dashpot, k_b·w + c_b·ẇ. Rigid ones: minus the fixed DOF's row of the element and link forces
/// that assembly leaves out (the deck element at the bearing, its structural damping, the track
/// links to the deck near it); an axle on `element` adds P·N of that DOF (loads on the deck).
struct BearingForce {
  /// "span<k>_start" / "span<k>_end" on a chain of simply supported spans; "support<k>" on a
  /// continuous deck (k from 1 at x = 0), the output names' stem.
  std::string name;
  std::size_t span = 0;  ///< the span it carries (0-based; an intermediate support: the span it ends)
  bool end = false;      ///< false: at the span's start
  bool rigid = true;
  double x = 0.0;        ///< [m] its position along the line
  DofWeights k, m, c;
  /// A deck element meeting at the bearing and its local DOF there (0: w0, 2: w1; fixed when
  /// rigid): one at a deck end, two over an intermediate support of a continuous deck.
  struct Element {
    PathElement element;
    int fixed_local = 0;
  };
  std::vector<Element> elements;
  /// [N] the self-weight it carries (deck and the track on it): g·m·L/2 on a simply supported
  /// span, from a static solve of the deck under its weight on a continuous one.
  double permanent = 0.0;
};

/// Assembled model. Matrices are symmetric, stored in full, n_dofs × n_dofs.
struct Structure {
  SparseMatrix M, C, K;
  Index n_dofs = 0;
  Index n_bridge_dofs = 0;
  Index n_track_dofs = 0;
  bool has_track = false;
  std::vector<double> span_start;        ///< [m] x of each span's left end
  std::vector<double> span_length;       ///< [m]
  std::vector<double> span_EI;           ///< [N·m²] bending stiffness of each span
  std::vector<PathElement> deck_elements;  ///< all spans, ordered by x
  std::vector<PathElement> rail_elements;  ///< empty without track
  std::vector<double> sleeper_x;         ///< [m] sleeper positions (empty without track)
  std::vector<Index> sleeper_dof, ballast_dof;  ///< per sleeper
  double deck_mass_per_m_used = 0.0;     ///< [kg/m] deck beam mass actually assembled, span 1
  /// Elements the loads travel along (rail_elements with track, else deck_elements).
  const std::vector<PathElement>& load_path() const {
    return has_track ? rail_elements : deck_elements;
  }
  double path_start() const;  ///< [m]
  double path_end() const;    ///< [m]
  std::vector<std::size_t> span_first_element;  ///< index into deck_elements, per span
  /// Per span its start then its end bearing; continuous deck: one per support, in x order.
  std::vector<BearingForce> bearings;
  /// Per span: the index into bearings of its start and its end bearing.
  std::vector<std::array<std::size_t, 2>> span_bearings;
  bool continuous = false;  ///< the spans form one continuous deck (BridgeParams::continuous)
  /// The deck elements of span `span` (0-based): [first, last) into deck_elements; InputError
  /// when there is no such span.
  std::pair<std::size_t, std::size_t> span_elements(std::size_t span) const;
  /// Deflection interpolation on span `span` (0-based) at x_local [m] from its left end, in
  /// [0, length]; throws InputError outside.
  PointCoupling deck_point(std::size_t span, double x_local) const;
  /// Bending moment [N·m] at x_local on span `span` (0-based): M = −EI·w''(x), sagging positive
  /// (w is positive down), from the Hermite elements' curvature; at a node between two elements
  /// the mean of both (exact when neither carries a point force, half the error of one
  /// otherwise), over an intermediate support of a continuous deck too (the moment is continuous
  /// there). InputError outside the span.
  DofWeights deck_moment(std::size_t span, double x_local) const;
  /// Shear force [N] at x_local: V = dM/dx = −EI·w‴(x) (so V = R_A − the loads left of x on a
  /// simply supported span), constant along each Hermite element; at a node the mean of both
  /// elements (exact when neither carries a point force). At a span's ends the span's own side
  /// (the shear jumps by the reaction over a support). InputError outside the span.
  DofWeights deck_shear(std::size_t span, double x_local) const;
  /// Rotation θ = dw/dx [rad] of the deck at the start (end = false) or end of span `span`:
  /// positive where the deck falls towards +x (a sagging span: > 0 at its start, < 0 at its end).
  /// On a continuous deck a span's end and the next one's start are the same node.
  DofWeights deck_end_rotation(std::size_t span, bool end) const;
  /// Deflection interpolation on the rail at x; throws InputError without track or outside it.
  PointCoupling rail_point(double x) const;

 private:
  // −EI × the mean, over the elements holding x_local, of w'' (order 2) or w‴ (order 3).
  DofWeights deck_derivative(std::size_t span, double x_local, int order) const;
};

/// Size limits that keep a mistyped element size from exhausting memory: per span and per
/// continuous deck (its dense modal-damping eigenproblem grows with the cube), and for the whole
/// rail.
constexpr int kMaxSpanElements = 1000;
constexpr int kMaxDeckElements = 2000;
constexpr int kMaxRailElements = 100000;

/// Assembles bridge (and track when given). Throws InputError on invalid parameters or sizes
/// beyond the limits above.
Structure build_structure(const BridgeParams& bridge, const std::optional<TrackParams>& track);

/// The sizes and masses the assembly would have, checked before anything is allocated (done by
/// build_structure too). InputError whose message starts with the scenario key it blames
/// ("bridge.element_size 0.001 m gives ..."), so that a scenario reader can point at its line.
void check_model_size(const BridgeParams& bridge, const std::optional<TrackParams>& track);

/// Coupling of a point on a sequence of beam elements (sorted by x0, contiguous).
/// Throws InputError naming `what` when x lies outside [first.x0, last.x0 + last.h].
PointCoupling point_on(const std::vector<PathElement>& elements, double x, const char* what);

}  // namespace viaduct::model
