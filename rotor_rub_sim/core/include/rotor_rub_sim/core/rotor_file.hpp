/// @file
/// A rotor file: a flexible rotor in YAML (docs/rotors.md), read into an
/// FeRotor and checked item by item.
///
///   material: {youngs_modulus_Pa: 211e9, shear_modulus_Pa: 81.2e9, density_kg_per_m3: 7810}
///   shaft:      # in order from node 0; `elements` repeats an entry
///     - {elements: 6, length_m: 0.25, outer_diameter_m: 0.05, inner_diameter_m: 0}
///   disks:      # by geometry (width and diameters, the file's material) or by mass and inertias
///     - {node: 2, width_m: 0.07, inner_diameter_m: 0.05, outer_diameter_m: 0.28}
///     - {node: 4, mass_kg: 32.6, polar_inertia_kg_m2: 0.33, diametral_inertia_kg_m2: 0.18}
///   bearings:   # bearings and seals: kxx kxy kyx kyy [N/m], cxx cxy cyx cyy [N s/m]; absent ones 0
///     - {node: 0, kxx: 1e6, kyy: 0.8e6}
///   unbalances: # m e [kg m] and the force's direction at spin angle 0 [rad, from +x]
///     - {node: 2, me_kg_m: 1e-4, phase_rad: 0}
///   rub_station: {node: 3, contact_radius_m: 0.05}  # where the stator is met, the surface's radius there
///                                                   # (read for the contact methods; not used yet)
///   probes:     # X/Y proximity probe pairs (their angles and signals are the scene's probe keys)
///     - {node: 0}
///
/// Or, in place of material, shaft, disks and bearings, the assembled
///   matrices: {nodes_z_m: [...], M: [[...]], K: [[...]], C: [[...]], G: [[...]]}
/// (4 DOF per node, [x, y, alpha, beta]; C and G optional; docs/rotors.md).
/// A shaft entry may carry its own `material`. Errors name the item (the
/// section and its index), the key, the value and the accepted range; an
/// unknown key names the nearest known one.
#pragma once

#include <string>

#include "rotor_rub_sim/core/fe_rotor.hpp"

namespace rotor_rub::core {

/// Throws std::invalid_argument (an unreadable file, a bad item) naming the
/// file and the item.
FeRotor load_rotor_file(const std::string& path);

}  // namespace rotor_rub::core
