//! The hub's side of pairing (see [`crate::pairing`] for the exchange): a connection whose
//! first frame is `PairStart`.

use std::net::SocketAddr;
use std::time::Duration;

use crate::frame::{Frame, PairChallenge, PairStart, Paired};
use crate::pairing::{HubExchange, MacLabel, from_hex, mac_hex, paired_parts, to_hex, verify_mac};
use crate::transport::{FrameReader, Outbox};

use super::Hub;
use super::outgoing::{error_outgoing, frame_outgoing, send};

/// Runs one pairing conversation; what happened, for the hub's event log. Every refusal is
/// also sent to the station as an `Error` frame.
pub(super) async fn serve(
    hub: &Hub,
    start: PairStart,
    reader: &mut FrameReader,
    out: &Outbox,
    peer: SocketAddr,
) -> String {
    match conversation(hub, start, reader, out, peer).await {
        Ok(outcome) => outcome,
        Err(refusal) => {
            send(out, error_outgoing(&refusal));
            format!("refused: {refusal}")
        }
    }
}

async fn conversation(
    hub: &Hub,
    start: PairStart,
    reader: &mut FrameReader,
    out: &Outbox,
    peer: SocketAddr,
) -> Result<String, String> {
    let authority = hub
        .store
        .pairing()
        .ok_or("this hub does not pair stations (it is a plain summary store)")?;
    let cert_sha256 = hub
        .certificate_sha256
        .ok_or("pairing needs TLS; this hub listens in plaintext")?;
    let ticket = authority
        .begin(&start.code_id, peer)
        .await
        .map_err(|r| r.message)?;
    let station_msg = from_hex(&start.pake).unwrap_or_default();
    let (hub_msg, key) =
        HubExchange::respond(&ticket.secret, &station_msg).map_err(|e| e.to_string())?;
    send(
        out,
        frame_outgoing(&Frame::PairChallenge(PairChallenge {
            pake: to_hex(&hub_msg),
        })),
    );
    let limit = Duration::from_millis(hub.config.hello_timeout_ms);
    let finish = match tokio::time::timeout(limit, reader.next_frame()).await {
        Ok(Ok(Some(Frame::PairFinish(f)))) => f,
        Ok(Ok(Some(other))) => return Err(format!("expected PairFinish, got {}", other.kind())),
        Ok(Ok(None)) => return Err("the station closed the connection".into()),
        Ok(Err(e)) => return Err(e.to_string()),
        Err(_) => return Err(format!("no PairFinish within {} ms", limit.as_millis())),
    };
    let transcript: [&[u8]; 4] = [
        &station_msg,
        &hub_msg,
        finish.csr_pem.as_bytes(),
        &cert_sha256,
    ];
    if !verify_mac(&key, MacLabel::StationFinish, &transcript, &finish.mac) {
        authority.failed(&start.code_id, peer).await;
        // A wrong code, or a relay in the middle: the same words as every other failure.
        return Err(crate::pairing::CODE_NOT_ACCEPTED.into());
    }
    let issued = authority
        .complete(&start.code_id, &finish.csr_pem)
        .await
        .map_err(|r| r.message)?;
    let mut paired = Paired {
        station_id: issued.station_id,
        patient_id: issued.patient_id,
        ca_pem: issued.ca_pem,
        cert_pem: issued.cert_pem,
        server_name: issued.server_name,
        mac: String::new(),
        patient_pseudonym: issued.patient_pseudonym,
    };
    let mut parts: Vec<&[u8]> = vec![&station_msg, &hub_msg];
    parts.extend(paired_parts(&paired));
    paired.mac = mac_hex(&key, MacLabel::HubPaired, &parts);
    let outcome = format!(
        "paired station {} for patient {}",
        paired.station_id, paired.patient_id
    );
    send(out, frame_outgoing(&Frame::Paired(paired)));
    Ok(outcome)
}
