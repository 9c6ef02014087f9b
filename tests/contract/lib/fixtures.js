'use strict';
// Scenarios the tests upload. The cup is the example of docs/robots/scenario-entries.md: an HSR whose open hand holds a cup
// on a side table between its fingers, so closing the gripper grasps it.
const fs = require('node:fs');
const path = require('node:path');
const { repoRoot } = require('./contract');

const cupOnASideTable = {
  name: 'cup_on_a_side_table',
  world: {
    bounds: { min: [-0.5, -0.5], max: [10.5, 10.5] },
    walls: [{ from: [0, 0], to: [10, 0] }, { from: [10, 0], to: [10, 10] }, { from: [10, 10], to: [0, 10] }, { from: [0, 10], to: [0, 0] }],
    obstacles: [{ name: 'side_table', box: { x: 2.75, y: 2.078, length: 0.3, width: 0.4 }, height: 0.556 }],
  },
  objects: [{ name: 'cup', shape: { kind: 'cylinder', radius: 0.03, length: 0.1 }, mass: 0.2, pose: { x: 2.685, y: 2.078, z: 0.606 } }],
  robots: [{
    id: 'hsr', model: 'hsr', start: { x: 2, y: 2, theta: 0 },
    joints: { arm_lift_joint: 0.3, arm_flex_joint: -1.5708, hand_motor_joint: 1.2 },
  }],
  steps: [{ name: 'wait', actions: [{ agent: 'hsr', wait: { duration: 55 } }] }],
};

/** A file of tests/fixtures as text. */
const fixture = (name) => fs.readFileSync(path.join(repoRoot, 'tests/fixtures', name), 'utf8');

module.exports = { cupOnASideTable, fixture };
