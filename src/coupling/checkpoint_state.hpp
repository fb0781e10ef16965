#pragma once
// The whole state of a coupled simulation in a checkpoint file (common/checkpoint_file.hpp), and its
// restoration into a freshly built Simulation, so that a run of N + M steps and a run of N steps,
// a checkpoint, a restart and M steps end bit for bit alike (same build, same thread count).
//
// What is saved: everything Simulation::step() and the queries after it depend on that is not
// rebuilt identically from the case:
//  - the fluid: the raw population buffer in storage precision with its ghost layer, the step
//    count (the AA parity) and the per-cell forces of the last step (lbm::FluidState);
//  - the body: position, velocity, body angular velocity and the attitude chart (the active Euler
//    set and its three angles, so the integrator continues in the same set);
//  - the coupling: step count, the moving window's origin and anchor, the momentum of the fluid
//    inside the body at the end of the last step (the next step's force needs its rate of
//    change), the last step's accelerations (the corrector's virtual-mass estimate for the next
//    step), the last step's observation (forces, slip, contact), the impact speed of each wall
//    contact in progress (it fixes that contact's wet restitution) and the sub-step timers;
//  - a fingerprint of what the case determines (grid, lattice, precision, boundaries, dx, dt, tau,
//    body force, gravity, motion kind, mass, markers, forcing, wall contact), checked on restore;
//  - the caller's data: the resolved case text, named numbers and named blobs (the run loop's
//    output schedule, accumulators, samples), stored as given.
// Not saved: what the case rebuilds exactly (units, markers, shape, copy lists, the particle-wall
// contact model's parameters), and the rigid body's switch_count() (a
// diagnostic that RigidBody cannot set; it restarts from 0).
//
// Restarting (the run loop's recipe): open the checkpoint (SimulationCheckpoint), read the resolved
// case text from caller().resolved_case, build the Simulation from it as at a fresh start, call
// restore(), hand the caller's values back to the loop, continue stepping.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/checkpoint_file.hpp"
#include "coupling/simulation.hpp"

namespace settle::coupling {

/// What the run loop stores beside the simulation; settle writes and returns it unchanged.
struct CheckpointCallerData {
  /// The resolved case (case.resolved.toml) the simulation was built from.
  std::string resolved_case;
  /// Named numbers (exact bits), e.g. an output schedule's next index.
  std::map<std::string, double> values;
  /// Named opaque records (e.g. accumulators serialised with RecordWriter).
  std::map<std::string, std::vector<std::byte>> blobs;
};

/// Writes the simulation's state and the caller's data to `file` atomically (common/checkpoint_file.hpp:
/// the previous file stays whole until the new one is complete). Throws CheckpointError on an
/// I/O failure, std::logic_error when a body step is half done (Simulation::between_body_steps).
///
/// Across processes (simulation.communicator() of more than one rank; every rank calls it) the
/// checkpoint comes in parts (docs/checkpoints.md, "Across processes"): each rank writes its block
/// of the fluid to checkpoint_parts_directory(file)/step-S/rank-R.bin; once every part is whole,
/// rank 0 writes `file` as the manifest (the rest of the state, the number of processes and the
/// step S of its parts) and removes the parts of other steps. A crash at any moment leaves a
/// manifest whose parts are complete. A failure on any rank is a CheckpointError on every rank.
void write_checkpoint(const Simulation& simulation, const CheckpointCallerData& caller,
                      const std::filesystem::path& file);

/// Where the parts of a checkpoint written across processes lie: FILE.parts beside it.
std::filesystem::path checkpoint_parts_directory(const std::filesystem::path& file);

/// The first entry under checkpoint_parts_directory(file) that settle did not write: anything but
/// step-NNNNNNNNNNNN folders holding rank-NNNNN.bin parts (and their .tmp) with a checkpoint's
/// signature; the folder itself when it is not a folder. None when every entry is a part, or
/// there is no such folder.
std::optional<std::filesystem::path> foreign_entry_in_parts(const std::filesystem::path& file);

/// Removes the parts under checkpoint_parts_directory(file), but those of the step folder named
/// `keep_step_folder` (empty: none) and anything foreign_entry_in_parts would name; then the
/// folders left empty. Best effort: what cannot be removed stays.
void remove_checkpoint_parts(const std::filesystem::path& file, const std::string& keep_step_folder = "");

/// A checkpoint's split: written by `ranks` processes (1: a whole checkpoint), the part of `rank`,
/// the step its parts were written at.
struct SplitRecord {
  int ranks = 1;
  int rank = 0;
  std::int64_t step = 0;
};

/// A checkpoint opened and verified (every CRC-32 checked, every record decoded), ready to restore.
class SimulationCheckpoint {
 public:
  /// Throws CheckpointError naming the file and the fault (missing, truncated, corrupt,
  /// other format version, malformed record).
  explicit SimulationCheckpoint(const std::filesystem::path& file);

  const CheckpointCallerData& caller() const { return caller_; }
  /// Coupled steps taken when the checkpoint was written, and the simulated time steps x dt.
  std::int64_t steps() const { return steps_; }
  double time_si() const { return time_si_; }
  /// settle version that wrote the file (informational).
  const std::string& written_by() const { return written_by_; }
  /// The processes of the run that wrote it (1 unless it is the manifest of parts).
  int processes() const { return split_.ranks; }

  /// Puts the saved state into `simulation`, which must have been built from the same case (the
  /// fingerprint is compared first: CheckpointError names the first quantity that differs, and
  /// the simulation is left unchanged) and split over as many processes as the run that wrote it
  /// (every rank calls it; each reads its own part). Can be called on several simulations.
  void restore(Simulation& simulation) const;

 private:
  CheckpointFile file_;
  CheckpointCallerData caller_;
  std::int64_t steps_ = 0;
  double time_si_ = 0.0;
  std::string written_by_;
  SplitRecord split_;
};

}  // namespace settle::coupling
