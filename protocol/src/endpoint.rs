//! Typed requests, in the spirit of postcard-rpc's endpoints: every [`Request`] variant has a struct
//! of the same name here that names its reply type ([`Endpoint::Reply`]). The wire stays the
//! [`Request`] enum (a struct encodes exactly as its variant's fields, so no byte changes); the
//! structs are how code on either side names a request:
//!
//! - the host calls `board.call(SetBus { baud, cycle_hz })` and gets `()` back, or
//!   `board.call(GetStatus)` and gets a [`Status`];
//! - the board implements [`Handler`], one method per endpoint with the endpoint's reply type, and
//!   [`dispatch`] turns a decoded [`Request`] into the [`Response`] to send.
//!
//! A new message is: a variant in [`Request`] (appended), a line in [`endpoints!`]'s table below
//! (the compiler then asks for the [`Handler`] method, and [`dispatch`] / [`Request::name`] are
//! exhaustive matches), and a call on the host.

use crate::MAX_CHUNK_LEN;
use crate::gait::GaitHeader;
use crate::message::{
    DeviceInfo, HealthLimits, JointIds, PlatformSetup, PlatformStatus, PlayCommand, ProtocolError,
    QueueCommand, Request, Response, ServoRead, ServoReadResult, ServoSelect, Settings, SlotInfo,
    Status, SteerCommand, SteerFamily, StreamConfig,
};
pub use crate::reply::{ChunkAccepted, Committed};
use crate::reply::{IntoResponse, Reply};

/// A request that names its reply.
pub trait Endpoint: Into<Request> {
    /// What a successful reply carries (`()` for an `Ack`).
    type Reply: Reply + IntoResponse;
    /// The request's name, for error messages ("GetStatus").
    const NAME: &'static str;
}

/// Contents of every gait slot (reply to [`ListGaits`]).
pub type Slots = heapless::Vec<SlotInfo, { crate::MAX_SLOTS }>;

/// The endpoint table: `Variant { fields } => Reply, handler_method;` for a variant with named
/// fields, `Variant => Reply, handler;` for a unit variant, `Variant(Struct) => Reply, handler;` for
/// a variant that wraps a struct of its own (the struct is then the endpoint).
macro_rules! endpoints {
    ($(
        $(#[$doc:meta])*
        $name:ident $({ $($field:ident : $ty:ty),* $(,)? })? $(( $wrapped:ident ))?
            => $reply:ty, $handler:ident;
    )*) => {
        $( endpoints!(@one $(#[$doc])* $name $({ $($field : $ty),* })? $(( $wrapped ))? => $reply); )*

        /// The board's side: one method per endpoint, returning the endpoint's reply or the error
        /// that travels back as data.
        pub trait Handler {
            $(
                $(#[$doc])*
                fn $handler(
                    &mut self,
                    request: endpoints!(@ty $name $(( $wrapped ))?),
                ) -> Result<$reply, ProtocolError>;
            )*
        }

        /// Answers `request` with `handler`: the request's typed method, its reply as a
        /// [`Response`] (errors as [`Response::Error`]).
        pub fn dispatch<H: Handler + ?Sized>(handler: &mut H, request: Request) -> Response {
            match request {
                $(
                    endpoints!(@pat inner; $name $({ $($field),* })? $(( $wrapped ))?) =>
                        respond(handler.$handler(
                            endpoints!(@build inner; $name $({ $($field),* })? $(( $wrapped ))?),
                        )),
                )*
            }
        }

        impl Request {
            /// The request's name ("GetStatus"), for error messages.
            pub fn name(&self) -> &'static str {
                match self {
                    $( endpoints!(@pat_any $name $({ $($field),* })? $(( $wrapped ))?) => stringify!($name), )*
                }
            }
        }
    };

    // One endpoint: the struct (unless the variant wraps one), From and Endpoint.
    (@one $(#[$doc:meta])* $name:ident { $($field:ident : $ty:ty),* } => $reply:ty) => {
        $(#[$doc])*
        #[derive(Debug, Clone, PartialEq)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        pub struct $name { $(pub $field: $ty),* }
        impl From<$name> for Request {
            fn from(r: $name) -> Self {
                let $name { $($field),* } = r;
                Request::$name { $($field),* }
            }
        }
        impl Endpoint for $name {
            type Reply = $reply;
            const NAME: &'static str = stringify!($name);
        }
    };
    (@one $(#[$doc:meta])* $name:ident => $reply:ty) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        pub struct $name;
        impl From<$name> for Request {
            fn from(_: $name) -> Self {
                Request::$name
            }
        }
        impl Endpoint for $name {
            type Reply = $reply;
            const NAME: &'static str = stringify!($name);
        }
    };
    (@one $(#[$doc:meta])* $name:ident ( $wrapped:ident ) => $reply:ty) => {
        impl From<$wrapped> for Request {
            fn from(r: $wrapped) -> Self {
                Request::$name(r)
            }
        }
        impl Endpoint for $wrapped {
            type Reply = $reply;
            const NAME: &'static str = stringify!($name);
        }
    };

    (@ty $name:ident) => { $name };
    (@ty $name:ident ( $wrapped:ident )) => { $wrapped };

    (@pat $bind:ident; $name:ident { $($field:ident),* }) => { Request::$name { $($field),* } };
    (@pat $bind:ident; $name:ident) => { Request::$name };
    (@pat $bind:ident; $name:ident ( $wrapped:ident )) => { Request::$name($bind) };

    (@pat_any $name:ident { $($field:ident),* }) => { Request::$name { .. } };
    (@pat_any $name:ident) => { Request::$name };
    (@pat_any $name:ident ( $wrapped:ident )) => { Request::$name(_) };

    (@build $bind:ident; $name:ident { $($field:ident),* }) => { $name { $($field),* } };
    (@build $bind:ident; $name:ident) => { $name };
    (@build $bind:ident; $name:ident ( $wrapped:ident )) => { $bind };
}

fn respond<R: IntoResponse>(result: Result<R, ProtocolError>) -> Response {
    match result {
        Ok(reply) => reply.into_response(),
        Err(e) => Response::Error(e),
    }
}

endpoints! {
    /// Who the board is: versions, capabilities, slots.
    GetDeviceInfo => DeviceInfo, get_device_info;
    /// State, fault, playback position, upload progress, counters.
    GetStatus => Status, get_status;
    /// Contents of every gait slot.
    ListGaits => Slots, list_gaits;
    /// Starts an upload into `slot`; `total_len` must equal `header.table_len()`.
    UploadBegin { slot: u8, header: GaitHeader, total_len: u32 } => (), upload_begin;
    /// Table bytes at `offset`, in order without gaps.
    UploadChunk { offset: u32, data: heapless::Vec<u8, MAX_CHUNK_LEN> } => ChunkAccepted, upload_chunk;
    /// Ends the upload: `crc` is the CRC-32 of all `total_len` bytes.
    UploadCommit { crc: u32 } => Committed, upload_commit;
    /// Drops the upload in progress.
    UploadAbort => (), upload_abort;
    /// Empties a slot (not the one playing).
    DeleteGait { slot: u8 } => (), delete_gait;
    /// Starts playback from standing.
    Play(PlayCommand) => (), play;
    /// Stops at the end of the current step.
    Stop => (), stop;
    /// Changes the step period scale while playing (1e-3).
    SetPeriodScale { scale: u16 } => (), set_period_scale;
    /// Bus settings, per-joint stiffness and limits.
    GetSettings => Settings, get_settings;
    /// Bus baud (bit/s) and cycle rate (Hz); only when not moving.
    SetBus { baud: u32, cycle_hz: u16 } => (), set_bus;
    /// Servo stiffness for the torque bias of `joint`, mN m/rad.
    SetStiffness { joint: u8, stiffness: u32 } => (), set_stiffness;
    /// Limits of `joint`, 1e-4 rad.
    SetLimits { joint: u8, min: i16, max: i16 } => (), set_limits;
    /// Torque on or off.
    SetTorque { servos: ServoSelect, enable: bool } => (), set_torque;
    /// Reboots servos (torque is off afterwards).
    RebootServos { servos: ServoSelect } => (), reboot_servos;
    /// Torque off on every servo at once, from any state.
    EmergencyStop => (), emergency_stop;
    /// Leaves the fault state once its cause is gone.
    ClearFault => (), clear_fault;
    /// Telemetry every `every` bus cycles (0 = off) outside streaming.
    SetTelemetry { every: u16 } => (), set_telemetry;
    /// Enters streaming mode from standing.
    EnterStreaming(StreamConfig) => (), enter_streaming;
    /// Leaves streaming mode, holding the last setpoint.
    LeaveStreaming => (), leave_streaming;
    /// Servo IDs of the joints of the table in `slot`, or of the selected gait with `None`
    /// (reply `None`: the slot is empty, or no gait is selected).
    GetJointMap { slot: Option<u8> } => Option<JointIds>, get_joint_map;
    /// Plays a gait next, at a step boundary, without standing still.
    QueueGait(QueueCommand) => (), queue_gait;
    /// Drops the queued gaits.
    ClearQueue => (), clear_queue;
    /// Sets the gaits `Steer` blends.
    SetSteerFamily(SteerFamily) => (), set_steer_family;
    /// The descending command: heading and speed.
    Steer(SteerCommand) => (), steer;
    /// Sets up the perturbation platform for the next runs.
    SetPlatform(PlatformSetup) => (), set_platform;
    /// No platform any more.
    ClearPlatform => (), clear_platform;
    /// The platform set up and its servo's state (`None`: none is set).
    GetPlatform => Option<PlatformStatus>, get_platform;
    /// Heat and supply limits: warn, and stop a walk at the end of its step.
    SetHealthLimits(HealthLimits) => (), set_health_limits;
    /// Reads registers of (or pings) one servo between bus cycles; collect with `GetServoRead`.
    ReadServo(ServoRead) => (), read_servo;
    /// The last finished servo read (`None`: pending, or none asked).
    GetServoRead => Option<ServoReadResult>, get_servo_read;
}
