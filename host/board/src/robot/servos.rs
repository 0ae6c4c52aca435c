//! What moves the virtual robot's servos between bus cycles. The board (firmware `Board`, bus
//! master, simulated wire, servo chain) is the same for every kind of servo; a [`ServoDynamics`]
//! says what else acts on the servos each cycle. [`PlannedLoads`] is the default: each servo's own
//! first-order lag (`dynamixel::sim`) carrying the planned torque of the slice being played. A
//! physics engine (a MuJoCo body) is another implementation: it reads the goals the bus just wrote
//! and sets the servos' positions and loads from its own simulation.

use dynamixel::sim::VirtualChain;
use firmware::controller::Controller;
use protocol::GaitTable;

use super::flash::VirtualFlash;

/// Acts on the servo chain once per bus cycle, before the bus traffic of that cycle.
pub trait ServoDynamics {
    /// `controller` is the board's state (read-only: the gait and slice being played);
    /// `chain` the servos on the wire; `now_us` the simulated time at the cycle's start.
    fn before_cycle(
        &mut self,
        controller: &Controller<VirtualFlash>,
        chain: &mut VirtualChain,
        now_us: u64,
    );
}

/// The servos' own lag model, loaded with the planned torque of the slice being played: the servo
/// must deliver `sign * torque`, so the load pushes the other way. Idle or standing: no load.
#[derive(Debug, Clone, Copy, Default)]
pub struct PlannedLoads;

impl ServoDynamics for PlannedLoads {
    fn before_cycle(&mut self, c: &Controller<VirtualFlash>, chain: &mut VirtualChain, _: u64) {
        let (Some(slot), Some((_, slice))) = (c.selected_slot(), c.playback()) else {
            return;
        };
        let Some(table) = c.store().table(slot).and_then(|b| GaitTable::parse(b).ok()) else {
            return;
        };
        for j in 0..table.joint_count() {
            let (Some(map), Some(torque)) = (table.joint(j), table.torque(usize::from(slice), j))
            else {
                continue;
            };
            let nm = protocol::units::torque_to_nm(torque) * f64::from(map.sign.as_i32());
            // A joint whose servo the chain lacks has no load to carry (the board faults on it).
            let _ = chain.set_external_torque(map.servo_id, -nm);
        }
    }
}
