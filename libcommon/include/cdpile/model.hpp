/// The objects every part of cdpile speaks about: a box, grains, contacts, frames.
///
/// SI units throughout (m, kg, s, rad; forces per unit thickness of the 2D slab in N/m,
/// impulses in N s/m). Grains are rigid disks; their mass and inertia are per unit
/// thickness: m = rho pi r^2, I = m r^2 / 2.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace cdpile {

using Vec2 = Eigen::Vector2d;

/// Ids that stand in the `j` column of a contact when its second body is a wall.
/// Grain ids are >= 0, so a contact is a wall contact exactly when j < 0.
enum WallId : std::int32_t {
  wall_floor = -1,  ///< the plane y = 0, outward normal +y
  wall_left = -2,   ///< the plane x = 0, outward normal +x
  wall_right = -3,  ///< the plane x = width, outward normal -x
};

/// Name of a wall id ("floor", "left", "right"), for messages and files.
const char* wall_name(std::int32_t wall_id);

/// The box in its own frame: floor y = 0, side walls x = 0 and x = width.
/// Tilting rotates gravity in this frame (docs/method.md, "The scheme"); the box never moves.
struct Box {
  double width = 0.0;   ///< distance between the side walls [m]
  double height = 0.0;  ///< height of the region used for output and figures [m]
};

/// What a grain is: a free disk, or one glued to the floor to make it rough.
enum class Species : std::uint8_t { free = 0, floor = 1 };

/// Grains as a structure of arrays (index = grain id). Static properties and the
/// dynamic state of one instant.
struct Grains {
  // static
  std::vector<double> radius;   ///< [m]
  std::vector<double> mass;     ///< per unit thickness [kg/m]
  std::vector<double> inertia;  ///< moment of inertia per unit thickness [kg m]
  std::vector<Species> species;
  // state
  std::vector<Vec2> position;            ///< centre [m]
  std::vector<Vec2> velocity;            ///< [m/s]
  std::vector<double> orientation;       ///< rotation angle, counter-clockwise [rad]
  std::vector<double> angular_velocity;  ///< counter-clockwise [rad/s]

  std::size_t size() const { return radius.size(); }
  void resize(std::size_t n);
  /// Appends a grain of density `rho` [kg/m^3] (mass and inertia per unit thickness).
  void add_disk(double r, double rho, const Vec2& x, Species s = Species::free);
};

/// Outcome of a contact's last local solve (the 2D exact solution of Signorini-Coulomb).
enum class ContactStatus : std::int8_t {
  open = 0,   ///< no impulse: the contact opens or stays open (R = 0)
  stick = 1,  ///< inside the Coulomb cone, zero relative tangential velocity
  slide = 2,  ///< on the cone, |R_t| = mu R_n, slipping
};

/// Contacts of one instant, as a table (one row per contact). Forces are the step's
/// impulses divided by the time step. The normal points from body j to grain i; the
/// tangent is the normal turned +90 degrees, t = (-n_y, n_x).
struct Contacts {
  std::vector<std::int32_t> i;  ///< grain id (always a grain)
  std::vector<std::int32_t> j;  ///< grain id, or a WallId (< 0)
  std::vector<Vec2> point;      ///< contact point [m]
  std::vector<Vec2> normal;     ///< unit normal, from j towards i
  std::vector<double> fn;       ///< normal force, >= 0 [N/m]
  std::vector<double> ft;       ///< tangential force along t [N/m]
  std::vector<double>
      gap;  ///< signed gap in the step's predicted configuration, < 0 is overlap [m]
  std::vector<ContactStatus> status;

  std::size_t size() const { return i.size(); }
  void clear();
  void reserve(std::size_t n);
  void resize(std::size_t n);  ///< n contacts, for the caller to fill
  void push_back(std::int32_t ii, std::int32_t jj, const Vec2& p, const Vec2& n, double f_n,
                 double f_t, double g, ContactStatus s);
};

/// One saved instant of a simulation: the grains' state and the contact forces.
struct Frame {
  std::int64_t step = 0;
  double time = 0.0;        ///< [s]
  double tilt_angle = 0.0;  ///< [rad]
  Grains grains;
  Contacts contacts;
};

}  // namespace cdpile
