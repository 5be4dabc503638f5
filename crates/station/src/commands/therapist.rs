//! `telerehab therapist`: the hub. Accepts many stations, prints a live line per summary,
//! acknowledges and stores every session's summaries under the store directory.

use anyhow::Context;
use netlink::{ServerTls, TherapistConfig, TherapistEvent, TherapistServer};
use std::io::Write;
use std::path::PathBuf;
use std::time::Duration;

/// `telerehab therapist`.
#[derive(Debug, clap::Args)]
pub struct TherapistArgs {
    /// Address to listen on, `host:port`.
    #[arg(long, default_value = "127.0.0.1:7878")]
    pub listen: String,
    /// Directory where each session's summaries are stored.
    #[arg(long)]
    pub store: PathBuf,
    /// Certificate chain (PEM) of this hub; with `--tls-key` enables TLS.
    #[arg(long, requires = "tls_key")]
    pub tls_cert: Option<PathBuf>,
    /// Private key (PEM) of this hub.
    #[arg(long, requires = "tls_cert")]
    pub tls_key: Option<PathBuf>,
}

/// Run the hub until SIGINT/SIGTERM.
pub fn run(args: TherapistArgs) -> anyhow::Result<()> {
    let listen = netlink::address::resolve("--listen", &args.listen)?;
    let tls = match (args.tls_cert, args.tls_key) {
        (Some(cert), Some(key)) => Some(ServerTls {
            cert_pem_path: cert,
            key_pem_path: key,
            client_ca_pem_path: None,
        }),
        _ => None,
    };
    std::fs::create_dir_all(&args.store)
        .with_context(|| format!("cannot create the store directory {}", args.store.display()))?;
    let config = TherapistConfig::new(listen, &args.store, tls);
    config.validate().context("therapist hub")?;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .thread_name("hub")
        .enable_all()
        .build()
        .context("cannot start the network runtime")?;
    netlink::server_stop::run_to_stop(runtime, async move {
        let (server, mut events) = TherapistServer::bind(config)
            .await
            .context("therapist hub")?;
        // The first line says where the hub listens (tests parse it; `--listen host:0` picks a port).
        println!(
            "listening on {} (store {})",
            server.local_addr(),
            args.store.display()
        );
        let _ = std::io::stdout().flush();
        let mut stop = std::pin::pin!(netlink::server_stop::stop_signal()?);
        loop {
            tokio::select! {
                // A stop first, however many events wait.
                biased;
                _ = &mut stop => break,
                ev = events.recv() => match ev {
                    Some(ev) => print_event(&ev),
                    None => break,
                },
            }
        }
        println!(
            "hub stopping; stations connected: {:?}",
            server.connected_stations()
        );
        server.shutdown(Duration::from_secs(2)).await;
        anyhow::Ok(())
    })
}

fn print_event(ev: &TherapistEvent) {
    println!("{ev}");
    let _ = std::io::stdout().flush();
}
