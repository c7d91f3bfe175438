//! `codegen sim`: the supervised plant in a browser — a local web server with one page and its JSON API
//! (docs/sim.md).

use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::PathBuf;
use std::process::ExitCode;

use codegen::config::SupervisorChoice;
use codegen::project::Project;
use codegen::sim::server::Server;
use codegen::sim::{sequence, Sim};

use super::Error;

/// Serve a page that draws the project's plants and supervisors, lists the events (enabled, disabled and
/// by whom), steps, reverts, resets and runs N events with the firmware's choice policy against the
/// steered virtual plant, and shows coverage and `check`'s findings on the graphs; until stopped
/// (Ctrl-C). The page calls a JSON API that scripts can use too (docs/sim.md).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The project manifest or model files' module (as `codegen run` takes it).
    manifest: PathBuf,
    /// The port to serve on (0: any free port, printed).
    #[arg(long, default_value_t = 8080)]
    port: u16,
    /// The address to bind: loopback by default, so only this machine sees the page.
    #[arg(long, default_value_t = IpAddr::V4(Ipv4Addr::LOCALHOST))]
    bind: IpAddr,
    /// Which supervisors to show and run: the full set, each reduced, or one monolithic supervisor, full
    /// or reduced (as `codegen run --supervisors`) [default: the manifest's `[runtime] supervisors`, else
    /// full].
    #[arg(long = "supervisors", id = "deploy", value_enum, value_name = "CHOICE")]
    deploy: Option<SupervisorChoice>,
}

/// Runs `sim`.
pub fn run(args: Args) -> Result<ExitCode, Error> {
    let mut project = Project::load(&args.manifest)?;
    // Which supervisors run is said on stderr: stdout's first line is the address.
    super::deploy(&mut project, args.deploy, true)?;
    let signals = project.state.as_ref().map(|s| s.check().map_err(|e| e.to_string()));
    let net = match (&project.hybrid, &project.net) {
        (Some(h), _) => Some(Ok(sequence::Net::plant(h.plant.net.clone(), h.plant.labels.clone()))),
        (None, Some(_)) => {
            project.sequence().map_err(|e| e.to_string()).map(|n| n.map(sequence::Net::sequence)).transpose()
        }
        (None, None) => None,
    };
    let mut sim = Sim::new(&project.name, project.set, project.runtime)?;
    if let Some(signals) = signals {
        sim = sim.with_signals(signals);
    }
    if let Some(net) = net {
        sim = sim.with_net(net);
    }
    let server = Server::bind(SocketAddr::new(args.bind, args.port))
        .map_err(|e| format!("{}:{}: {e}", args.bind, args.port))?;
    let addr = server.addr().map_or_else(|| format!("{}:{}", args.bind, args.port), |a| a.to_string());
    println!("codegen sim: {} on http://{addr}/ (Ctrl-C stops)", sim.name);
    server.serve(&mut sim);
    Ok(ExitCode::SUCCESS)
}
