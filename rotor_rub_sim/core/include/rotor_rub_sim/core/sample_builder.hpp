// Builds the method-independent Sample from a method's kinematics and force.
#pragma once

#include "rotor_rub_sim/core/model.hpp"
#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

// g and unbalance_dir: the state's contact geometry and the unbalance's
// direction (cos phi, sin phi) of d.angle_rad, where the caller has them.
// loads: the state's free loads (a flexible rotor's, whose spin coupling
// takes the modes in), or null: the Jeffcott's from k.
inline Sample make_sample(const JeffcottModel& m, double t_s, const Kinematics& k, const DriveState& d,
                          const ContactGeometry& g, const Vec2& unbalance_dir, double normal_force_N,
                          double tangential_force_N, bool in_contact, const JeffcottModel::FreeLoads* loads = nullptr) {
  // A motor's spin acceleration depends on the contact forces: the drive
  // state d carries the reference's until here.
  Sample s;
  s.drive = d;
  if (m.motor()) {
    s.drive.accel_rad_per_s2 =
        m.accelerations(d, g, loads ? *loads : m.free_loads(k, d, unbalance_dir), normal_force_N, tangential_force_N)
            .spin_rad_per_s2;
  }
  s.t_s = t_s;
  s.kin = k;
  s.kin.rotor_pos += m.frame_shift();  // the casing's frame (a rigid stator's offset)
  s.kin.stator_pos += m.frame_shift();
  s.probe_displacement_m = s.kin.rotor_pos;  // a flexible rotor's methods set their probe node's
  s.penetration_m = g.penetration_m;
  s.sliding_velocity_m_per_s = g.sliding_velocity_m_per_s;
  s.in_contact = in_contact;
  s.normal_force_N = normal_force_N;
  s.contact_force_on_rotor_N = JeffcottModel::contact_force_on_rotor(g, normal_force_N, tangential_force_N);
  s.friction_force_N = tangential_force_N;
  s.drive_torque_N_m = m.drive_torque_N_m(k, s.drive, g, unbalance_dir, normal_force_N, tangential_force_N);
  s.friction_torque_N_m = m.friction_torque_N_m(tangential_force_N);
  return s;
}

inline Sample make_sample(const JeffcottModel& m, double t_s, const Kinematics& k, const DriveState& d,
                          double normal_force_N, double tangential_force_N, bool in_contact) {
  return make_sample(m, t_s, k, d, m.contact_geometry(k, d), m.unbalance_dir(d.angle_rad), normal_force_N,
                     tangential_force_N, in_contact);
}

}  // namespace rotor_rub::core
