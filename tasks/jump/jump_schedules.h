#pragma once
/// The jumps' difficulty z and what it schedules (thesis §3.6.1 "Curriculum and Scheduling"):
/// ρ from z, the control frequency and the P-VAE offset coefficient from ρ, and the Table 3.1
/// curriculum that raises z. Pure functions; z in metres throughout.
#include <string>

#include "podium/character/curriculum.h"

namespace podium::tasks::jump {

/// High jump: z is the bar height. Obstacle jump: z is the width of a 50 cm high box (§3.6.1).
enum class JumpKind { high_jump, obstacle };
/// "high_jump" or "obstacle"; `where` names the config path in the error.
JumpKind parse_jump_kind(const std::string& name, const std::string& where);
const char* jump_kind_name(JumpKind kind);

/// ρ = 2z − 1 (high jump) or ρ = z (obstacle jump).
double difficulty_ratio(JumpKind kind, double z_m);
/// f_control = 10 + 20·clip(ρ, 0, 1) Hz, rounded to the nearest whole-Hz divisor of sim_hz (a tie
/// goes to the lower rate), so a control step is a whole number of simulation steps (World needs
/// sim_hz = k·control_hz) and the rate changes only a few times over the curriculum (each change
/// needs a new env). At 600 Hz the rates are 10, 12, 15, 20, 24, 25, 30 Hz: ρ = 0 → 10, 0.5 → 20,
/// 1 → 30. Throws base::UserError for a sim_hz that is not a whole number ≥ 30.
double control_hz_for(double rho, double sim_hz);
/// c_offset = 48 − 33·clip(ρ, 0, 1): eq. 3.4's largest mean offset norm, tightened as z rises.
double offset_coefficient(double rho);

/// Table 3.1 as a character::ThresholdCurriculum: z from z_min by Δz, each iteration's average
/// sample reward accumulated, z += Δz when the accumulator exceeds R_T (then it restarts at 0),
/// never past z_max. High jump 0.50 → 2.00 m, Δz 0.01, R_T 30; obstacle 0.05 → 2.50 m, Δz 0.05,
/// R_T 50.
character::ThresholdCurriculum::Config difficulty_curriculum(JumpKind kind);

}  // namespace podium::tasks::jump
