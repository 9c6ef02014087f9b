#include "physics/physics_world.hpp"

#include <algorithm>
#include <btBulletDynamicsCommon.h>

#include "core/error.hpp"

namespace hrisim::physics {
namespace {

/// Sequential-impulse iterations per step (Bullet's default is 10).
constexpr int kSolverIterations = 20;
/// Half the side of the floor slab, m.
constexpr double kFloorHalfSize = 500.0;
/// Friction coefficient of every body.
constexpr double kFriction = 0.8;

btVector3 to_bullet(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

btTransform to_bullet(const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.rotation());
  return btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), to_bullet(pose.translation()));
}

Eigen::Isometry3d from_bullet(const btTransform& transform) {
  const btQuaternion q = transform.getRotation();
  const btVector3& t = transform.getOrigin();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translate(Eigen::Vector3d(t.x(), t.y(), t.z()));
  pose.rotate(Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()));
  return pose;
}

std::unique_ptr<btCollisionShape> make_shape(const robots::Shape& shape) {
  switch (shape.kind) {
    case robots::Shape::Kind::box: return std::make_unique<btBoxShape>(to_bullet(0.5 * shape.size));
    case robots::Shape::Kind::cylinder:
      return std::make_unique<btCylinderShapeZ>(btVector3(shape.radius, shape.radius, 0.5 * shape.length));
    case robots::Shape::Kind::sphere: return std::make_unique<btSphereShape>(shape.radius);
    case robots::Shape::Kind::capsule: return std::make_unique<btCapsuleShapeZ>(shape.radius, shape.length);
  }
  throw core::Error(core::ErrorCode::internal, "unknown shape kind");
}

/// Robot links are kinematic like people and the map, which Bullet never pairs with each other; this
/// broadphase group and the dispatcher below pair them, so a robot's contacts with people and walls are
/// reported (never resolved: both sides are immovable).
constexpr int kRobotGroup = 1 << 6;

class ContactDispatcher : public btCollisionDispatcher {
 public:
  using btCollisionDispatcher::btCollisionDispatcher;
  bool needsCollision(const btCollisionObject* a, const btCollisionObject* b) override {
    const bool robot_a = a->getBroadphaseHandle()->m_collisionFilterGroup & kRobotGroup;
    const bool robot_b = b->getBroadphaseHandle()->m_collisionFilterGroup & kRobotGroup;
    if (!a->checkCollideWith(b) || !b->checkCollideWith(a)) return false;  // a held object and the hand holding it
    if (robot_a || robot_b) return a->getUserIndex2() != b->getUserIndex2() || !(robot_a && robot_b);  // not two links of one robot
    return btCollisionDispatcher::needsCollision(a, b);
  }
};

void clear(btJointFeedback& feedback) {
  feedback.m_appliedForceBodyA.setZero();
  feedback.m_appliedForceBodyB.setZero();
  feedback.m_appliedTorqueBodyA.setZero();
  feedback.m_appliedTorqueBodyB.setZero();
}

}  // namespace

struct PhysicsWorld::Impl {
  explicit Impl(double dt_in) : dt(dt_in) {
    world.setGravity(btVector3(0, 0, -kGravity));
    world.getSolverInfo().m_numIterations = kSolverIterations;
    // Penetrations of any depth are resolved apart from velocities: they add no energy, and a held
    // object resting a little deep in a table does not load the grip.
    world.getSolverInfo().m_splitImpulse = 1;

  }

  double dt;
  btDefaultCollisionConfiguration configuration;
  ContactDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};

  struct Body {
    std::unique_ptr<btTriangleMesh> mesh;  ///< the walls' triangles (outlives the shape that uses it)
    std::unique_ptr<btCollisionShape> shape;
    std::unique_ptr<btDefaultMotionState> motion;
    std::unique_ptr<btRigidBody> body;
    BodyOwner owner;
    double mass = 0.0;
    bool enabled = true;
    int holder = -1;
    std::unique_ptr<btFixedConstraint> hold;  ///< the grasp's joint while held
    std::unique_ptr<btJointFeedback> hold_feedback;  ///< on the heap: the joint keeps its address
    /// Bodies it does not collide with: the hand that holds it, and after a release that hand until
    /// they no longer overlap (fingers closed into it would kick it away).
    std::vector<int> hand;
  };
  std::vector<Body> bodies;

  int add(std::unique_ptr<btCollisionShape> shape, double mass, const btTransform& pose, BodyOwner owner, bool kinematic) {
    Body body;
    btVector3 inertia(0, 0, 0);
    if (mass > 0.0) shape->calculateLocalInertia(mass, inertia);
    body.motion = std::make_unique<btDefaultMotionState>(pose);
    body.body = std::make_unique<btRigidBody>(btRigidBody::btRigidBodyConstructionInfo(mass, body.motion.get(), shape.get(), inertia));
    if (kinematic) {
      body.body->setCollisionFlags(body.body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
      body.body->setActivationState(DISABLE_DEACTIVATION);
    }
    body.body->setUserIndex(static_cast<int>(bodies.size()));
    body.body->setUserIndex2(owner.index);
    body.shape = std::move(shape);
    body.owner = std::move(owner);
    body.mass = mass;
    body.body->setFriction(kFriction);
    body.body->setRestitution(0.0);
    insert(body);
    bodies.push_back(std::move(body));
    return static_cast<int>(bodies.size()) - 1;
  }

  /// Adds the body to the world in its broadphase group (robot links in their own).
  void insert(Body& body) {
    if (body.owner.kind == BodyOwner::Kind::robot) {
      world.addRigidBody(body.body.get(), kRobotGroup, btBroadphaseProxy::AllFilter);
    } else {
      world.addRigidBody(body.body.get());
    }
  }

  /// Whether body `other` stops body `self` (see PhysicsWorld::clearance).
  bool solid_for(const Body& self, int other) const {
    const Body& body = bodies[other];
    if (other == floor || body.mass > 0.0) return false;  // held objects keep their mass
    return !(body.owner.kind == self.owner.kind && body.owner.index == self.owner.index);
  }

  int floor = -1;

  /// The nearest contact between one body and those solid for it.
  class Clearance : public btCollisionWorld::ContactResultCallback {
   public:
    Clearance(const Impl& impl, const Body& self, double reach) : impl_(impl), self_(self), nearest_(reach) { m_closestDistanceThreshold = reach; }
    bool needsCollision(btBroadphaseProxy* proxy) const override {
      return impl_.solid_for(self_, static_cast<const btCollisionObject*>(proxy->m_clientObject)->getUserIndex());
    }
    btScalar addSingleResult(btManifoldPoint& point, const btCollisionObjectWrapper*, int, int, const btCollisionObjectWrapper*, int, int) override {
      nearest_ = std::min(nearest_, static_cast<double>(point.getDistance()));
      return 0;
    }
    double nearest() const { return nearest_; }

   private:
    const Impl& impl_;
    const Body& self_;
    double nearest_;
  };

  Body& at(int id) {
    if (id < 0 || id >= static_cast<int>(bodies.size())) throw core::Error(core::ErrorCode::internal, "no physics body " + std::to_string(id));
    return bodies[id];
  }
};

PhysicsWorld::PhysicsWorld(double dt) : impl_(std::make_unique<Impl>(dt)) {}
PhysicsWorld::~PhysicsWorld() {
  for (auto& body : impl_->bodies) {
    if (body.hold) impl_->world.removeConstraint(body.hold.get());
  }
  for (auto& body : impl_->bodies) {
    if (body.enabled) impl_->world.removeRigidBody(body.body.get());
  }
}

int PhysicsWorld::add_floor_and_walls(std::span<const world::Segment> segments, double height) {
  // A large slab rather than a plane: boxes resting on a box get their whole contact manifold at once
  // (a plane gathers it over several steps, and the first lone contact tips and slides them).
  const int floor = impl_->add(std::make_unique<btBoxShape>(btVector3(kFloorHalfSize, kFloorHalfSize, 0.5)), 0.0,
                               btTransform(btQuaternion::getIdentity(), btVector3(0, 0, -0.5)), {BodyOwner::Kind::map, -1, "floor"}, false);
  impl_->floor = floor;
  if (segments.empty()) return floor;
  auto mesh = std::make_unique<btTriangleMesh>();
  for (const world::Segment& segment : segments) {
    const btVector3 a(segment.a.x(), segment.a.y(), 0.0), b(segment.b.x(), segment.b.y(), 0.0), up(0, 0, height);
    mesh->addTriangle(a, b, b + up);
    mesh->addTriangle(a, b + up, a + up);
  }
  auto shape = std::make_unique<btBvhTriangleMeshShape>(mesh.get(), true);
  const int walls = impl_->add(std::move(shape), 0.0, btTransform::getIdentity(), {BodyOwner::Kind::map, -1, "walls"}, false);
  impl_->bodies[walls].mesh = std::move(mesh);
  return walls;
}

int PhysicsWorld::add_static_prism(const std::vector<Eigen::Vector2d>& polygon, double height, BodyOwner owner) {
  auto hull = std::make_unique<btConvexHullShape>();
  for (const Eigen::Vector2d& p : polygon) {
    hull->addPoint(btVector3(p.x(), p.y(), 0.0), false);
    hull->addPoint(btVector3(p.x(), p.y(), height), false);
  }
  hull->recalcLocalAabb();
  hull->setMargin(0.0);
  return impl_->add(std::move(hull), 0.0, btTransform::getIdentity(), std::move(owner), false);
}

int PhysicsWorld::add_kinematic(const robots::Shape& shape, const Eigen::Isometry3d& pose, BodyOwner owner) {
  return impl_->add(make_shape(shape), 0.0, to_bullet(pose), std::move(owner), true);
}

int PhysicsWorld::add_dynamic(const robots::Shape& shape, double mass, const Eigen::Isometry3d& pose, BodyOwner owner) {
  if (!(mass > 0.0)) throw core::Error(core::ErrorCode::bad_request, "a movable object needs a positive mass");
  return impl_->add(make_shape(shape), mass, to_bullet(pose), std::move(owner), false);
}

void PhysicsWorld::set_kinematic_pose(int body, const Eigen::Isometry3d& pose) {
  Impl::Body& entry = impl_->at(body);
  entry.motion->setWorldTransform(to_bullet(pose));
  entry.body->setWorldTransform(to_bullet(pose));
  // Clearance queries find bodies by their broadphase boxes before the next step would move them.
  if (entry.enabled) impl_->world.updateSingleAabb(entry.body.get());
}

double PhysicsWorld::clearance(int body, const Eigen::Isometry3d& pose, double reach) {
  Impl::Body& entry = impl_->at(body);
  entry.motion->setWorldTransform(to_bullet(pose));
  entry.body->setWorldTransform(to_bullet(pose));
  Impl::Clearance nearest(*impl_, entry, reach);
  impl_->world.contactTest(entry.body.get(), nearest);
  return nearest.nearest();
}

void PhysicsWorld::place(int body, const Eigen::Isometry3d& pose) {
  Impl::Body& entry = impl_->at(body);
  entry.motion->setWorldTransform(to_bullet(pose));
  entry.body->setWorldTransform(to_bullet(pose));
  entry.body->setLinearVelocity(btVector3(0, 0, 0));
  entry.body->setAngularVelocity(btVector3(0, 0, 0));
  entry.body->activate(true);
}

void PhysicsWorld::set_velocity(int body, const Twist& velocity) {
  btRigidBody& moved = *impl_->at(body).body;
  moved.setLinearVelocity(btVector3(velocity.linear.x(), velocity.linear.y(), velocity.linear.z()));
  moved.setAngularVelocity(btVector3(velocity.angular.x(), velocity.angular.y(), velocity.angular.z()));
}

void PhysicsWorld::set_enabled(int body, bool enabled) {
  Impl::Body& entry = impl_->at(body);
  if (entry.enabled == enabled) return;
  entry.enabled = enabled;
  if (enabled) {
    impl_->insert(entry);
  } else {
    impl_->world.removeRigidBody(entry.body.get());
  }
}

void PhysicsWorld::set_friction(int body, double friction) { impl_->at(body).body->setFriction(friction); }

void PhysicsWorld::attach(int body, int holder, std::span<const int> hand) {
  Impl::Body& held = impl_->at(body);
  Impl::Body& by = impl_->at(holder);
  if (held.holder >= 0) detach(body);
  held.holder = holder;
  // The joint's frames: the held body's pose as it is now, in each body's frame.
  held.hold = std::make_unique<btFixedConstraint>(*by.body, *held.body, by.body->getWorldTransform().inverse() * held.body->getWorldTransform(),
                                                  btTransform::getIdentity());
  held.hold_feedback = std::make_unique<btJointFeedback>();
  clear(*held.hold_feedback);
  held.hold->setJointFeedback(held.hold_feedback.get());
  impl_->world.addConstraint(held.hold.get(), true);
  for (const int part : held.hand) held.body->setIgnoreCollisionCheck(impl_->at(part).body.get(), false);  // a hand still letting go
  held.hand.assign(hand.begin(), hand.end());
  for (const int finger : held.hand) held.body->setIgnoreCollisionCheck(impl_->at(finger).body.get(), true);
  // Contacts with the hand found before are dropped with the body's pairs; the next step pairs it anew.
  impl_->world.getBroadphase()->getOverlappingPairCache()->cleanProxyFromPairs(held.body->getBroadphaseHandle(), &impl_->dispatcher);
  held.body->forceActivationState(DISABLE_DEACTIVATION);
}

void PhysicsWorld::detach(int body) {
  Impl::Body& held = impl_->at(body);
  if (held.holder < 0) return;
  held.holder = -1;
  impl_->world.removeConstraint(held.hold.get());
  held.hold.reset();
  held.hold_feedback.reset();
  held.body->forceActivationState(ACTIVE_TAG);
}

int PhysicsWorld::holder(int body) const { return impl_->at(body).holder; }

Wrench PhysicsWorld::hold_load(int body) const {
  const Impl::Body& held = impl_->at(body);
  if (held.holder < 0) return {};
  const btJointFeedback& load = *held.hold_feedback;
  return {Eigen::Vector3d(load.m_appliedForceBodyB.x(), load.m_appliedForceBodyB.y(), load.m_appliedForceBodyB.z()),
          Eigen::Vector3d(load.m_appliedTorqueBodyB.x(), load.m_appliedTorqueBodyB.y(), load.m_appliedTorqueBodyB.z())};
}

void PhysicsWorld::step() {
  for (Impl::Body& body : impl_->bodies) {
    // The solver adds each step's joint forces to the feedback.
    if (body.hold) clear(*body.hold_feedback);
  }
  for (std::size_t b = 0; b < impl_->bodies.size(); ++b) {
    Impl::Body& released = impl_->bodies[b];
    if (released.holder >= 0 || released.hand.empty()) continue;
    // A released body collides with the hand again once no part of it overlaps the body.
    const bool overlaps = std::any_of(released.hand.begin(), released.hand.end(), [&](int part) {
      const std::optional<ContactPoint> contact = deepest_contact(part, static_cast<int>(b));
      return contact && contact->distance < 0.0;
    });
    if (overlaps) continue;
    for (const int part : released.hand) released.body->setIgnoreCollisionCheck(impl_->bodies[part].body.get(), false);
    released.hand.clear();
  }
  // One fixed step of dt, no interpolation substeps: the same work every tick.
  impl_->world.stepSimulation(impl_->dt, 0, impl_->dt);
}

Eigen::Isometry3d PhysicsWorld::pose(int body) const { return from_bullet(impl_->at(body).body->getWorldTransform()); }

Twist PhysicsWorld::velocity(int body) const {
  const btRigidBody& moving = *impl_->at(body).body;
  const btVector3 linear = moving.getLinearVelocity(), angular = moving.getAngularVelocity();
  return {Eigen::Vector3d(linear.x(), linear.y(), linear.z()), Eigen::Vector3d(angular.x(), angular.y(), angular.z())};
}

const BodyOwner& PhysicsWorld::owner(int body) const { return impl_->at(body).owner; }

std::vector<std::pair<int, int>> PhysicsWorld::touching() const {
  std::vector<std::pair<int, int>> pairs;
  btDispatcher& dispatcher = impl_->dispatcher;
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    bool touches = false;
    for (int c = 0; c < manifold->getNumContacts(); ++c) touches |= manifold->getContactPoint(c).getDistance() <= kContactDistance;
    if (!touches) continue;
    int a = manifold->getBody0()->getUserIndex(), b = manifold->getBody1()->getUserIndex();
    if (a > b) std::swap(a, b);
    pairs.emplace_back(a, b);
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

Wrench PhysicsWorld::external_wrench(std::span<const int> bodies, const Eigen::Vector3d& point) const {
  const auto to_eigen = [](const btVector3& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); };
  const auto in_group = [&](int body) { return std::find(bodies.begin(), bodies.end(), body) != bodies.end(); };
  Wrench wrench;
  const auto add = [&](const Eigen::Vector3d& force, const Eigen::Vector3d& at) {
    wrench.force += force;
    wrench.torque += (at - point).cross(force);
  };
  btDispatcher& dispatcher = impl_->dispatcher;
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    const bool first = in_group(manifold->getBody0()->getUserIndex()), second = in_group(manifold->getBody1()->getUserIndex());
    if (first == second) continue;
    for (int c = 0; c < manifold->getNumContacts(); ++c) {
      const btManifoldPoint& contact = manifold->getContactPoint(c);
      // The solver's impulses push the manifold's first body along these directions, its second against them.
      const btVector3 impulse = contact.m_normalWorldOnB * contact.getAppliedImpulse() + contact.m_lateralFrictionDir1 * contact.m_appliedImpulseLateral1 +
                                contact.m_lateralFrictionDir2 * contact.m_appliedImpulseLateral2;
      const Eigen::Vector3d force = to_eigen(impulse) / impl_->dt;
      add(first ? force : Eigen::Vector3d(-force), to_eigen(first ? contact.getPositionWorldOnA() : contact.getPositionWorldOnB()));
    }
  }
  for (std::size_t b = 0; b < impl_->bodies.size(); ++b) {
    const Impl::Body& held = impl_->bodies[b];
    if (held.holder < 0 || !in_group(held.holder) || in_group(static_cast<int>(b))) continue;
    // The holder receives the opposite of what its joint applies to the held body.
    const Wrench load = hold_load(static_cast<int>(b));
    const Eigen::Vector3d centre = to_eigen(held.body->getWorldTransform().getOrigin());
    add(-load.force, centre);
    wrench.torque -= load.torque;
  }
  return wrench;
}

std::optional<ContactPoint> PhysicsWorld::deepest_contact(int a, int on) {
  // Bullet's normal lies on the second body of a result and points to its first.
  class Deepest : public btCollisionWorld::ContactResultCallback {
   public:
    explicit Deepest(const btCollisionObject* on) : on_(on) { m_closestDistanceThreshold = kContactDistance; }
    btScalar addSingleResult(btManifoldPoint& point, const btCollisionObjectWrapper*, int, int, const btCollisionObjectWrapper* second, int, int) override {
      if (point.getDistance() > kContactDistance || (found && point.getDistance() >= found->distance)) return 0;
      const bool on_second = second->getCollisionObject() == on_;
      const btVector3 normal = on_second ? point.m_normalWorldOnB : -point.m_normalWorldOnB;
      const btVector3& at = on_second ? point.getPositionWorldOnB() : point.getPositionWorldOnA();
      found = ContactPoint{Eigen::Vector3d(at.x(), at.y(), at.z()), Eigen::Vector3d(normal.x(), normal.y(), normal.z()), point.getDistance()};
      return 0;
    }
    std::optional<ContactPoint> found;

   private:
    const btCollisionObject* on_;
  };
  const Impl::Body& surface = impl_->at(on);
  Deepest deepest(surface.body.get());
  impl_->world.contactPairTest(impl_->at(a).body.get(), surface.body.get(), deepest);
  return deepest.found;
}

}  // namespace hrisim::physics
