//! Joint names for a board's records (telemetry, proprioception) and setpoints, by the rule of
//! `dbot record` (`board::record::joint_names`): each joint is the model joint driven by the servo
//! the active gait's table names for it; without that table, the model's servo joints in joint-map
//! order when the counts agree; `J<n>` where neither can say.
//!
//! The board does not send its tables back, so a `Board` keeps the tables it uploaded itself and
//! follows which one the firmware has selected (firmware/src/controller/commands.rs): the slot
//! played last, or an upload into the selected slot or into a board with none selected. For a gait
//! it did not upload, it asks the board for the servo IDs of the selected table (`GetJointMap`)
//! and names each joint by its servo ID through the model.

use planner::model::Model;

/// What a `Board` knows for naming its joints.
#[derive(Debug, Clone)]
pub struct JointNaming {
    model: Model,
    /// Tables this `Board` uploaded, by slot.
    tables: [Option<Vec<u8>>; protocol::MAX_SLOTS],
    /// The slot the board has selected, as far as this `Board` saw it.
    active: Option<u8>,
    /// The board's own answer to `GetJointMap`: the slot it has selected and that table's servo
    /// IDs in joint-map order (used when this `Board` did not upload that table).
    board_map: Option<(u8, Vec<u8>)>,
    /// The last answer of [`Self::names`], (count, names), until something above changes
    /// (parsing the selected table again for every record was about a tenth of the host's work
    /// in a physics robot's step, docs/performance.md).
    memo: std::cell::RefCell<Option<(usize, Vec<String>)>>,
}

impl JointNaming {
    /// Names from `model`, no table known yet.
    pub fn new(model: Model) -> Self {
        Self {
            model,
            tables: Default::default(),
            active: None,
            board_map: None,
            memo: std::cell::RefCell::new(None),
        }
    }

    pub fn set_model(&mut self, model: Model) {
        self.memo.get_mut().take();
        self.model = model;
    }

    /// `table` was committed into `slot`.
    pub fn uploaded(&mut self, slot: u8, table: Vec<u8>) {
        self.memo.get_mut().take();
        if let Some(t) = self.tables.get_mut(usize::from(slot)) {
            *t = Some(table);
        }
        if self.active.is_none_or(|a| a == slot) {
            self.active = Some(slot);
        }
    }

    /// The table this `Board` uploaded into `slot`, and the model naming its joints (for the
    /// library's check of a faster-than-planned play).
    pub fn uploaded_table(&self, slot: u8) -> (Option<&[u8]>, &Model) {
        let table = self
            .tables
            .get(usize::from(slot))
            .and_then(|t| t.as_deref());
        (table, &self.model)
    }

    /// The board accepted `Play` of `slot` (it selects that slot's table).
    pub fn played(&mut self, slot: u8) {
        self.memo.get_mut().take();
        self.active = Some(slot);
    }

    /// The board reported `map` for its selected gait (`None`: nothing selected).
    pub fn board_reported(&mut self, map: Option<protocol::JointIds>) {
        self.memo.get_mut().take();
        self.board_map = map.map(|m| (m.slot, m.servo_ids.to_vec()));
        if let Some((slot, _)) = &self.board_map {
            self.active = Some(*slot);
        }
    }

    /// The names of the board's first `count` joints (joint-map order): by the servo IDs of the
    /// table this `Board` uploaded for the selected slot, else by those the board reported for it,
    /// else the model's servo joints in order.
    pub fn names(&self, count: usize) -> Vec<String> {
        if let Some((c, names)) = self.memo.borrow().as_ref()
            && *c == count
        {
            return names.clone();
        }
        let names = self.name_joints(count);
        *self.memo.borrow_mut() = Some((count, names.clone()));
        names
    }

    fn name_joints(&self, count: usize) -> Vec<String> {
        let table = self
            .active
            .and_then(|s| self.tables.get(usize::from(s))?.as_deref())
            .and_then(|b| protocol::GaitTable::parse(b).ok());
        if table.is_none()
            && let Some((slot, ids)) = &self.board_map
            && Some(*slot) == self.active
            && ids.len() == count
        {
            return ::board::record::joint_names_by_ids(&self.model, ids);
        }
        ::board::record::joint_names(&self.model, table.as_ref(), count)
    }
}
