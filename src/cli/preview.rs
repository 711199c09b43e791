//! `rtlang preview SCENE [--port N] [--bind ADDR] [--allow-host NAME]
//! [--open]`: starts the live preview
//! server, prints its URL and serves until Ctrl-C. The work is in
//! `rtlang::preview`.

use std::net::IpAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::time::Duration;

use clap::Args;

use rtlang::preview::{Config, Preview};
use rtlang::render::interrupt;

/// Arguments of `rtlang preview`.
#[derive(Args)]
pub struct PreviewArgs {
    /// The scene file.
    scene: PathBuf,
    /// Port to listen on (0 picks a free one).
    #[arg(long, default_value_t = 8300)]
    port: u16,
    /// Address to listen on. Anything but a loopback address exposes the
    /// scene's render to the network (a warning is printed). With 0.0.0.0
    /// or ::, every address of this machine is accepted in `Host`.
    #[arg(long, default_value = "127.0.0.1")]
    bind: IpAddr,
    /// Another name the page may be reached by, such as the machine's
    /// network name (`NAME` or `NAME:PORT`, repeatable). Requests naming
    /// any other host are refused, against DNS rebinding.
    #[arg(long = "allow-host", value_name = "NAME")]
    allow_host: Vec<String>,
    /// Open the page in the default browser.
    #[arg(long)]
    open: bool,
    /// Scene parameter override `name=value` (repeatable).
    #[arg(short = 'D', value_parser = super::parse_define)]
    define: Vec<(String, String)>,
}

/// Runs the command.
pub fn run(args: PreviewArgs) -> ExitCode {
    if !args.bind.is_loopback() {
        errln!(
            "warning: listening on {}: anyone who can reach this address can see the render",
            args.bind
        );
    }
    let stop = match interrupt::stop_flag() {
        Ok(flag) => flag,
        Err(e) => {
            errln!("error: cannot catch Ctrl-C ({e}), so the preview could not stop cleanly");
            return ExitCode::FAILURE;
        }
    };
    let config = Config {
        scene: args.scene,
        options: rtlang::lang::Options {
            defines: args.define,
            stop: Some(stop),
            ..rtlang::lang::Options::default()
        },
        bind: args.bind,
        port: args.port,
        allow_hosts: args.allow_host,
    };
    let preview = match Preview::start(config) {
        Ok(p) => p,
        Err(e) => {
            errln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    outln!("rtlang preview: {}  (Ctrl-C stops)", preview.url());
    if args.open {
        open_browser(&preview.url());
    }
    while !stop.load(Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(100));
    }
    errln!("stopping the preview");
    preview.stop();
    ExitCode::SUCCESS
}

/// Asks the desktop to open `url`; a failure only prints a hint.
fn open_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else {
        "xdg-open"
    };
    if let Err(e) = std::process::Command::new(opener).arg(url).spawn() {
        errln!("warning: cannot open a browser ({opener}: {e}); open {url} yourself");
    }
}
