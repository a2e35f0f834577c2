#pragma once
/// \file A train's wheels rolling along a structure's load path: where each wheel is on the rail
/// (a ContactPath, core/contact_path.hpp, that the coupled kernels of solve/coupled.hpp read), the
/// irregularity under it, and the wheel–rail contact law (linearised Hertz). The same contacts in
/// a structure's modal coordinates are solve::modal_contacts (over the structure's ModalReduction).

#include <memory>

#include "viaduct/core/contact_path.hpp"
#include "viaduct/load/irregularity.hpp"
#include "viaduct/load/train.hpp"
#include "viaduct/model/structure.hpp"

namespace viaduct::load {

/// [N/m] linearised Hertz stiffness of one axle (both wheels) of static load `axle_load` [N]:
/// 2 · 1.5 (P/2)^{1/3} / G, G = 4.57e-8 R^-0.149 m/N^{2/3} (Zhai's conical tread), R [m].
double hertz_stiffness(double axle_load, double wheel_radius);

/// The irregularity under a wheel at x [m] along the line, positive down (a dip): minus the
/// profile, faded in over [x_from, x_from + taper] and out over [x_end, x_end + taper] by cosine
/// ramps, 0 outside [x_from, x_end + taper] and without a profile.
double irregularity_at(const load::RailProfile* profile, double x, double x_from, double x_end, double taper);

/// The wheels of `train` rolling at `speed` [m/s] along the load path of `s` (which must outlive
/// the result): the first axle at the path's start at t = t_start [s], the others on rigid ground
/// behind it until they reach it; the rail under each as Hermite weights of the element's DOFs,
/// and the irregularity irregularity_at() gives with `profile` (may be null), fading in from
/// x_start − run_in [m] and out past the path's end over `taper` [m]. On a track, within
/// `transition` [m] of either end of the path a wheel's load passes between rigid ground and the
/// rail gradually, the rail's level under it weighted alike (a cosine from 0 at the end to 1):
/// a free rail end, deflecting several times more than the track, would otherwise be a dip that
/// every wheel hits. InputError when the transition reaches the bridge. The path's time
/// t is the kernel's minus t_start (a run-in starts at kernel time 0 with t_start = run_in / v).
std::unique_ptr<ContactPath> train_contacts(const model::Structure& s, const load::Train& train, double speed,
                                            const load::RailProfile* profile, double run_in, double taper,
                                            double t_start = 0.0, double transition = 10.0);

/// InputError when a track's end transition [m] is negative or reaches the bridge.
void require_transition(const model::Structure& s, double transition);

}  // namespace viaduct::load
