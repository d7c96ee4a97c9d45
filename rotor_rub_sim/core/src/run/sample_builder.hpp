// Builds the method-independent Sample from a method's kinematics and force:
// the station's part; the rotor model finishes it (rotor_model.hpp's
// finish_sample: the probes, the drive torque's share of the rotor's lateral
// motion).
#pragma once

#include <stdexcept>

#include "rotor_rub_sim/core/model.hpp"
#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

// g: the state's contact geometry. loads: the state's free loads (the rotor
// model's), which a motor's spin acceleration takes in: needed under a
// motor drive, unused under the prescribed one.
inline Sample make_sample(const StationModel& m, double t_s, const Kinematics& k, const DriveState& d,
                          const ContactGeometry& g, double normal_force_N, double tangential_force_N, bool in_contact,
                          const FreeLoads* loads = nullptr) {
  // A motor's spin acceleration depends on the contact forces: the drive
  // state d carries the reference's until here.
  Sample s;
  s.drive = d;
  if (m.motor()) {
    if (loads == nullptr) throw std::logic_error("make_sample: a motor drive's sample needs the state's free loads");
    s.drive.accel_rad_per_s2 = m.accelerations(d, g, *loads, normal_force_N, tangential_force_N).spin_rad_per_s2;
  }
  s.t_s = t_s;
  s.kin = k;
  s.kin.rotor_pos += m.frame_shift();  // the casing's frame (a rigid stator's offset)
  s.kin.stator_pos += m.frame_shift();
  s.probe_displacement_m = s.kin.rotor_pos;  // a flexible rotor's model sets its probe node's
  s.penetration_m = g.penetration_m;
  s.sliding_velocity_m_per_s = g.sliding_velocity_m_per_s;
  s.in_contact = in_contact;
  s.normal_force_N = normal_force_N;
  s.contact_force_on_rotor_N = StationModel::contact_force_on_rotor(g, normal_force_N, tangential_force_N);
  s.friction_force_N = tangential_force_N;
  s.drive_torque_N_m = m.station_drive_torque_N_m(s.drive, tangential_force_N);
  s.friction_torque_N_m = m.friction_torque_N_m(tangential_force_N);
  return s;
}

// The same, the geometry from k (the prescribed drive).
inline Sample make_sample(const StationModel& m, double t_s, const Kinematics& k, const DriveState& d,
                          double normal_force_N, double tangential_force_N, bool in_contact) {
  return make_sample(m, t_s, k, d, m.contact_geometry(k, d), normal_force_N, tangential_force_N, in_contact);
}

}  // namespace rotor_rub::core
