#pragma once
// How the contact forces between bodies are found and summed. Two implementations share the
// contact law: FastContacts (cell grid, Verlet lists, parallel) and BruteForceContacts (every
// pair, serial, obviously correct), which the tests keep as the oracle for the fast path.
#include "box.hpp"
#include "contact_params.hpp"
#include "particles.hpp"

namespace granudrag {

class ContactForces {
 public:
  virtual ~ContactForces() = default;
  // Called after every position update; returns true when it rebuilt its pair lists
  // (positions may then have been wrapped into the box).
  virtual bool update_lists(Particles& p, const Box& box) = 0;
  // Adds the forces and torques of all body-body contacts to p.f and p.torque.
  virtual void accumulate(Particles& p, const Box& box, const ContactParams& c, double dt,
                          bool update_history) = 0;
  // Energy stored in the normal springs of all touching pairs.
  virtual double elastic_energy(const Particles& p, const Box& box,
                                const ContactParams& c) const = 0;
  // Number of bodies touching particle `body` (an intruder) at the last force evaluation.
  virtual int contacts_of(int body) const = 0;
  // Number of touching body-body pairs at the last force evaluation.
  virtual long contact_count() const = 0;
};

}  // namespace granudrag
