#pragma once
/// \file Trains as vehicles on the structure (docs/vehicles.md): the vehicle model a scenario
/// chooses, the rail profile the wheels see, and runs of the coupled system through the
/// integrator's one face (solve::Integrator::run_coupled): coupled Newmark on every DOF
/// (Method::newmark) or with the structure in modal coordinates and the vehicles in physical ones
/// (Method::modal, the fast path: the modes up to modal.max_frequency_hz / modal.n_modes, with the
/// dropped modes' static correction at the contacts and the outputs when modal.static_correction,
/// all held by one solve::ModalReduction), or coupled IDA on the same modal system (Method::ida:
/// adaptive, contact events as roots).

#include <memory>

#include "viaduct/load/contacts.hpp"
#include "viaduct/load/irregularity.hpp"
#include "viaduct/load/vehicle.hpp"
#include "viaduct/solve/coupled.hpp"
#include "viaduct/solve/modal.hpp"
#include "viaduct/study/simulation.hpp"

namespace viaduct::study {

// The contact paths and the wheel–rail law are the loads' (load/contacts.hpp).
using load::hertz_stiffness;
using load::irregularity_at;
using load::require_transition;
using load::train_contacts;

/// True when the integrator `s` chooses takes the structure in its modes under vehicles
/// (solve::method_traits: the fast path and IDA): the answer prepare_model and the accuracy
/// warnings use (simulate_vehicles asks its integrator, which agrees).
bool vehicles_on_modes(const RunSettings& s);

/// Most load-path DOFs the static correction of the vehicle fast path takes (its dense residual
/// flexibility between them, solve::ModalReduction::contact_residual(): 8 n_path² bytes, 128 MiB here).
constexpr Index kMaxResidualPathDofs = 4096;

/// The modes `settings.modal` selects, reduced for the coupled vehicle kernels (the
/// solve::ModalReduction constructor with contact DOFs: the structure's load path), with the
/// static correction (settings.static_correction) at the load path and at `outputs` (functionals
/// of the structure's DOFs; those simulate_vehicles() records: vehicle_outputs()). `kept_hz`, when
/// given, receives the modes' frequencies [Hz]. InputError when no mode is kept or the path has
/// more than kMaxResidualPathDofs DOFs for the correction; SolverError from the eigensolver or a
/// singular K.
std::shared_ptr<const solve::ModalReduction> vehicle_reduction(const model::Structure& s, const ModalSettings& settings,
                                                               const std::vector<solve::Functional>& outputs = {},
                                                               Vector* kept_hz = nullptr);

/// The displacement outputs of a vehicle run, in the structure's DOFs and in this order: each
/// station's main point (the deck, or the rail without a deck), the rail above each deck station
/// (empty when it has none), each load effect's functional.
std::vector<solve::Functional> vehicle_outputs(const std::vector<ResolvedStation>& stations,
                                               const std::vector<LoadEffect>& effects);

/// The vehicles of `train` under `s.vehicle` (sprung or multibody), scaled by s.load_factor
/// (one rail line carries its share of each vehicle), with their contacts; `detail` receives the
/// unscaled model (DOF and body names). InputError for forces, a train the model cannot take,
/// or invalid parameters.
solve::LinearVehicle linear_vehicle(const load::Train& train, const RunSettings& s, load::TrainVehicles* detail = nullptr);

/// The profile the wheels see on structure `s` (null for a smooth rail): drawn from the
/// spectrum over the run-in, the load path and the taper past it (at least one longest
/// wavelength long, from the run-in's start: the same for every train and speed), or the
/// measured one, which must cover them. InputError otherwise.
std::shared_ptr<const load::RailProfile> rail_profile(const model::Structure& s, const IrregularitySettings& irr);

/// One run of `train` at `speed` [m/s] with vehicles (settings.vehicle.model is sprung or
/// multibody): station histories (unfiltered), load effects when `m` has them, and the vehicles'
/// contact forces and car-body accelerations. Method newmark, modal or ida (`m` prepared for it:
/// the modal basis for modal and ida); InputError for an invalid case, SolverError from the kernel.
RunResult simulate_vehicles(const PreparedModel& m, const load::Train& train, double speed, const RunSettings& settings);

}  // namespace viaduct::study
