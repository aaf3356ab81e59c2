#include "mjcf_import.hpp"

#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>

#include <mujoco/mujoco.h>

namespace mbrt::codegen {

namespace {

using ModelPtr = std::unique_ptr<mjModel, decltype(&mj_deleteModel)>;
using DataPtr = std::unique_ptr<mjData, decltype(&mj_deleteData)>;

Eigen::Vector3d vec3(const mjtNum* x) { return {x[0], x[1], x[2]}; }

// mjData's row-major 3x3 matrices.
Eigen::Matrix3d mat3(const mjtNum* x) {
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(x);
}

class MjcfReader {
 public:
  MjcfReader(const mjModel& m, const mjData& d, ImportedModel& out) : m_(m), d_(d), out_(out) {}

  // Bodies without joints are welded to their parent: MuJoCo's body_weldid
  // names the moving body (or the world, 0) each belongs to.
  void add_bodies() {
    body_of_.assign(static_cast<size_t>(m_.nbody), kGround);
    for (int i = 1; i < m_.nbody; ++i) {
      const int weld = m_.body_weldid[i];
      if (weld == 0) {
        if (m_.body_mass[i] > 0.0) out_.notes.push_back("body '" + name(mjOBJ_BODY, i) + "' is fixed to the world");
        continue;
      }
      if (weld != i) {
        body_of_[static_cast<size_t>(i)] = body_of_[static_cast<size_t>(weld)];
        merge_part(out_.bodies[static_cast<size_t>(body_of_[static_cast<size_t>(i)])].mass, mass_part(i));
        out_.notes.push_back("body '" + name(mjOBJ_BODY, i) + "' (no joint) is merged into '" + name(mjOBJ_BODY, weld) +
                             "'");
        continue;
      }
      ImportedBody b;
      b.name = name(mjOBJ_BODY, i);
      b.orientation = Eigen::Quaterniond(d_.xquat[4 * i], d_.xquat[4 * i + 1], d_.xquat[4 * i + 2], d_.xquat[4 * i + 3]);
      b.mass = mass_part(i);
      out_.bodies.push_back(b);
      body_of_[static_cast<size_t>(i)] = static_cast<int>(out_.bodies.size()) - 1;
      add_joint(i);
    }
  }

  void add_equalities() {
    for (int e = 0; e < m_.neq; ++e) {
      const std::string eq = "equality '" + name(mjOBJ_EQUALITY, e) + "'";
      if (!m_.eq_active[e]) {
        out_.warnings.push_back(eq + " is inactive at the start and left out");
        continue;
      }
      if (m_.eq_type[e] != mjEQ_CONNECT && m_.eq_type[e] != mjEQ_WELD) {
        throw std::runtime_error(out_.source + ": " + eq +
                                 ": only connect and weld equalities can be imported (as spherical and fixed joints)");
      }
      const int b1 = m_.eq_obj1id[e], b2 = m_.eq_obj2id[e];
      const mjtNum* data = m_.eq_data + mjNEQDATA * e;
      ImportedJoint j;
      j.name = name(mjOBJ_EQUALITY, e);
      j.body1 = body_of_[static_cast<size_t>(b1)];
      j.body2 = body_of_[static_cast<size_t>(b2)];
      // connect: anchor (data 0-2) in body1's frame; weld: anchor in body2's frame.
      const int anchor_body = m_.eq_type[e] == mjEQ_CONNECT ? b1 : b2;
      j.point = vec3(d_.xpos + 3 * anchor_body) + mat3(d_.xmat + 9 * anchor_body) * vec3(data);
      j.type = m_.eq_type[e] == mjEQ_CONNECT ? JointType::spherical : JointType::fixed;
      require_satisfied(e, eq);
      out_.joints.push_back(j);
    }
  }

  // What the compiled model has that mbrt's model has not.
  void warn_unsupported() {
    if (m_.nu > 0) out_.warnings.push_back(list(mjOBJ_ACTUATOR, m_.nu, "actuators") + " are not imported");
    if (m_.ntendon > 0) out_.warnings.push_back(list(mjOBJ_TENDON, m_.ntendon, "tendons") + " are not imported");
    int colliding = 0;
    for (int g = 0; g < m_.ngeom; ++g) colliding += (m_.geom_contype[g] || m_.geom_conaffinity[g]) ? 1 : 0;
    if (colliding > 1 && !(m_.opt.disableflags & mjDSBL_CONTACT)) {
      out_.warnings.push_back(std::to_string(colliding) + " geoms can collide; contacts are not imported");
    }
    if (m_.opt.density != 0.0 || m_.opt.viscosity != 0.0) {
      out_.warnings.push_back("the medium's density and viscosity (fluid forces) are not imported");
    }
  }

 private:
  std::string name(mjtObj type, int id) const {
    const char* n = mj_id2name(&m_, type, id);
    if (n && *n) return n;
    const char* kind = type == mjOBJ_BODY    ? "body"
                       : type == mjOBJ_JOINT ? "joint"
                       : type == mjOBJ_EQUALITY ? "equality"
                                                : "object";
    return std::string(kind) + std::to_string(id);
  }

  // "actuators 'a', 'b'" (the first three names).
  std::string list(mjtObj type, int count, const std::string& what) const {
    std::string s = std::to_string(count) + " " + what;
    for (int i = 0; i < count && i < 3; ++i) s += (i ? ", '" : " ('") + name(type, i) + "'";
    return s + (count > 3 ? ", ...)" : ")");
  }

  // Body i's mass, centre of mass (xipos) and principal inertia in its
  // inertial frame (ximat), world axes.
  MassPart mass_part(int i) const {
    MassPart p;
    const Eigen::Matrix3d r = mat3(d_.ximat + 9 * i);
    p.mass = m_.body_mass[i];
    p.com = vec3(d_.xipos + 3 * i);
    p.inertia = r * vec3(m_.body_inertia + 3 * i).asDiagonal() * r.transpose();
    return p;
  }

  void add_joint(int i) {
    const std::string body = "body '" + name(mjOBJ_BODY, i) + "'";
    if (m_.body_jntnum[i] > 1) {
      throw std::runtime_error(out_.source + ": " + body + " has " + std::to_string(m_.body_jntnum[i]) +
                               " joints; mbrt takes one joint per body (split it into a chain of bodies with mass)");
    }
    const int jnt = m_.body_jntadr[i];
    const int dof = m_.jnt_dofadr[jnt];
    const int qpos = m_.jnt_qposadr[jnt];
    const std::string joint = "joint '" + name(mjOBJ_JOINT, jnt) + "'";
    if (m_.jnt_limited[jnt]) {
      out_.warnings.push_back(joint + ": limits [" + number_text(m_.jnt_range[2 * jnt]) + ", " +
                              number_text(m_.jnt_range[2 * jnt + 1]) + "] are not enforced (mbrt has no joint limits)");
    }
    if (m_.dof_frictionloss[dof] != 0.0) {
      out_.warnings.push_back(joint + ": frictionloss " + number_text(m_.dof_frictionloss[dof]) + " is not supported and left out");
    }
    const int type = m_.jnt_type[jnt];
    if (type == mjJNT_FREE || type == mjJNT_BALL) {
      if (m_.jnt_stiffness[jnt] != 0.0 || m_.dof_damping[dof] != 0.0 || m_.dof_armature[dof] != 0.0) {
        out_.warnings.push_back(joint + ": stiffness, damping and armature of a " +
                                std::string(type == mjJNT_FREE ? "free" : "ball") + " joint are not supported and left out");
      }
      if (type == mjJNT_FREE) {
        out_.notes.push_back(body + " (free " + joint + ") is a free body");
        return;
      }
    }
    ImportedJoint j;
    j.name = name(mjOBJ_JOINT, jnt);
    j.type = type == mjJNT_HINGE ? JointType::revolute : type == mjJNT_SLIDE ? JointType::prismatic : JointType::spherical;
    j.body1 = body_of_[static_cast<size_t>(m_.body_parentid[i])];
    j.body2 = body_of_[static_cast<size_t>(i)];
    j.point = vec3(d_.xanchor + 3 * jnt);
    j.axis = vec3(d_.xaxis + 3 * jnt).normalized();
    if (j.type != JointType::spherical) {
      // MuJoCo's joint spring pulls towards qpos_spring (springref), mbrt's
      // towards rest measured from the position at t = 0 (qpos0).
      j.armature = m_.dof_armature[dof];
      if (!(m_.opt.disableflags & mjDSBL_PASSIVE)) {
        j.damping = m_.dof_damping[dof];
        j.stiffness = m_.jnt_stiffness[jnt];
        j.rest = j.stiffness != 0.0 ? m_.qpos_spring[qpos] - m_.qpos0[qpos] : 0.0;
      }
    }
    out_.joints.push_back(j);
  }

  // mbrt's spherical and fixed joints hold what they find at t = 0; an
  // equality MuJoCo does not find satisfied at qpos0 (a weld's relpose that
  // asks for another pose) cannot be one of them. Its rows' residuals are
  // MuJoCo's efc_pos.
  void require_satisfied(int e, const std::string& eq) const {
    for (int r = 0; r < d_.nefc; ++r) {
      if (d_.efc_type[r] != mjCNSTR_EQUALITY || d_.efc_id[r] != e || std::abs(d_.efc_pos[r]) <= 1e-9) continue;
      throw std::runtime_error(out_.source + ": " + eq + " is not satisfied at qpos0 (residual " +
                               number_text(d_.efc_pos[r]) + "); mbrt's joints hold the relative pose of t = 0");
    }
  }

  const mjModel& m_;
  const mjData& d_;
  ImportedModel& out_;
  std::vector<int> body_of_;  // per MuJoCo body: index in out_.bodies, or kGround
};

}  // namespace

ImportedModel import_mjcf(const std::string& path) {
  std::array<char, 1000> error{};
  const ModelPtr m(mj_loadXML(path.c_str(), nullptr, error.data(), static_cast<int>(error.size())), &mj_deleteModel);
  if (!m) {
    std::string message = error.data();
    message.erase(message.find_last_not_of(" \n") + 1);
    throw std::runtime_error(path + ": " + message);
  }
  const DataPtr d(mj_makeData(m.get()), &mj_deleteData);
  mj_forward(m.get(), d.get());  // kinematics at qpos0
  ImportedModel out;
  out.name = m->names;  // the model's name comes first (mjmodel.h, names)
  out.source = path;
  out.format = "MJCF";
  if (!(m->opt.disableflags & mjDSBL_GRAVITY)) out.gravity = vec3(m->opt.gravity);
  out.step = m->opt.timestep;
  MjcfReader reader(*m, *d, out);
  reader.add_bodies();
  reader.add_equalities();
  reader.warn_unsupported();
  require_masses(out, "bodies merged into it included");
  return out;
}

}  // namespace mbrt::codegen
