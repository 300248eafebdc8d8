#include "nonlinear/contact_results.hpp"

namespace c2d::nonlinear {

using constraints::ContactReport;

void store_contact_results(const ContactReport& report, int nn, core::Results& r) {
  r.globals["contact_pressure_max"] = report.p_max;
  r.globals["contact_length"] = report.length;
  r.globals["contact_force"] = report.total_force;
  r.globals["contact_penetration"] = report.max_penetration;
  if (report.friction) {
    r.globals["contact_tangential_force"] = report.tangent_force;
    r.globals["contact_stick_nodes"] = report.stick_nodes;
    r.globals["contact_slip_nodes"] = report.slip_nodes;
  }
  VecX gap = VecX::Zero(nn), pressure = VecX::Zero(nn), force = VecX::Zero(nn);
  for (const auto& cn : report.nodes) {
    gap[cn.node] = cn.gap;
    pressure[cn.node] = cn.pressure;
    force[cn.node] = cn.force;
  }
  for (const auto& p : report.plates) {
    r.globals["plate_ux/" + p.name] = p.u.x();
    r.globals["plate_uy/" + p.name] = p.u.y();
    r.globals["plate_rotation/" + p.name] = p.rotation;
    r.globals["plate_fx/" + p.name] = p.force.x();
    r.globals["plate_fy/" + p.name] = p.force.y();
    r.globals["plate_moment/" + p.name] = p.moment;
  }
  r.point_fields["contact_gap"] = gap;
  r.point_fields["contact_pressure"] = pressure;
  r.point_fields["contact_force"] = force;
  if (report.friction) {
    VecX shear = VecX::Zero(nn), slip = VecX::Zero(nn), state = VecX::Zero(nn);
    for (const auto& cn : report.nodes) {
      shear[cn.node] = cn.shear;
      slip[cn.node] = cn.accumulated_slip;
      state[cn.node] = static_cast<double>(cn.state);
    }
    r.point_fields["contact_shear"] = shear;
    r.point_fields["contact_slip"] = slip;
    r.point_fields["contact_state"] = state;
  }
}

}  // namespace c2d::nonlinear
