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
    if (robot_a || robot_b) return a->getUserIndex2() != b->getUserIndex2() || !(robot_a && robot_b);  // not two links of one robot
    return btCollisionDispatcher::needsCollision(a, b);
  }
};

}  // namespace

struct PhysicsWorld::Impl {
  explicit Impl(double dt_in) : dt(dt_in) {
    world.setGravity(btVector3(0, 0, -kGravity));
    world.getSolverInfo().m_numIterations = kSolverIterations;
    world.getSolverInfo().m_splitImpulse = 1;  // penetrations resolved without adding energy
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
    btTransform held_offset;  ///< pose in the holder's frame while held
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

void PhysicsWorld::attach(int body, int holder) {
  Impl::Body& held = impl_->at(body);
  const Impl::Body& by = impl_->at(holder);
  held.holder = holder;
  held.held_offset = by.body->getWorldTransform().inverse() * held.body->getWorldTransform();
  // Held, the body moves with its holder: kinematic until released.
  impl_->world.removeRigidBody(held.body.get());
  held.body->setMassProps(0.0, btVector3(0, 0, 0));
  held.body->setCollisionFlags(held.body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
  held.body->setActivationState(DISABLE_DEACTIVATION);
  held.body->setLinearVelocity(btVector3(0, 0, 0));
  held.body->setAngularVelocity(btVector3(0, 0, 0));
  impl_->insert(held);
}

void PhysicsWorld::detach(int body) {
  Impl::Body& held = impl_->at(body);
  if (held.holder < 0) return;
  held.holder = -1;
  impl_->world.removeRigidBody(held.body.get());
  btVector3 inertia(0, 0, 0);
  held.shape->calculateLocalInertia(held.mass, inertia);
  held.body->setMassProps(held.mass, inertia);
  held.body->setCollisionFlags(held.body->getCollisionFlags() & ~btCollisionObject::CF_KINEMATIC_OBJECT);
  held.body->forceActivationState(ACTIVE_TAG);
  held.body->setLinearVelocity(btVector3(0, 0, 0));
  held.body->setAngularVelocity(btVector3(0, 0, 0));
  impl_->insert(held);
}

int PhysicsWorld::holder(int body) const { return impl_->at(body).holder; }

void PhysicsWorld::step() {
  for (Impl::Body& body : impl_->bodies) {
    if (body.holder < 0) continue;
    const btTransform pose = impl_->bodies[body.holder].body->getWorldTransform() * body.held_offset;
    body.motion->setWorldTransform(pose);
    body.body->setWorldTransform(pose);
  }
  // One fixed step of dt, no interpolation substeps: the same work every tick.
  impl_->world.stepSimulation(impl_->dt, 0, impl_->dt);
}

Eigen::Isometry3d PhysicsWorld::pose(int body) const { return from_bullet(impl_->at(body).body->getWorldTransform()); }

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

}  // namespace hrisim::physics
