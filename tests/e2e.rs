//! The end-to-end tests, one binary: every module below was a test binary of its own, and each of them
//! linked codegen and the firmware again (about 100 MB of debug build apiece); one binary links them
//! once. A module keeps its file name, so a test is found and run as before by its module:
//! `cargo test -p end-to-end --test e2e loopback::` (or `-- --exact loopback::a_burst_…`).

mod agv;
mod burst;
mod cell;
mod factory;
mod hybrid;
mod layouts;
mod link_faults;
mod livelock;
mod loopback;
mod mutants;
mod net;
mod pico;
mod plc;
mod plc_state;
mod race;
mod safe_state;
mod stalls;
mod state_firmware;
mod station;
mod timers;
mod vendor;
mod wide;
