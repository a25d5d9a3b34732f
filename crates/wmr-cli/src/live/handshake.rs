//! The WebSocket handshake of `--live`: the subprotocol chosen from what the client offers
//! (any of [`SUBPROTOCOLS`]), or a refusal that says what was offered and what is accepted.

use tungstenite::handshake::server::{ErrorResponse, Request, Response};
use tungstenite::http::{HeaderValue, StatusCode};

use super::protocol::SUBPROTOCOLS;

/// The subprotocols a request offers (every `sec-websocket-protocol` header, split at
/// commas, trimmed), each cut to 64 characters. All of them are looked at (the request
/// itself is bounded by the handshake's limits: a client offering 17 with ours last was
/// refused); a refusal quotes the first [`QUOTED`].
fn offered(req: &Request) -> Vec<String> {
    req.headers()
        .get_all("sec-websocket-protocol")
        .iter()
        .flat_map(|h| String::from_utf8_lossy(h.as_bytes()).split(',').map(|s| s.trim().to_owned()).collect::<Vec<_>>())
        .filter(|s| !s.is_empty())
        .map(|s| s.chars().filter(|c| !c.is_control()).take(64).collect())
        .collect()
}

/// Offers a refusal quotes at most (the rest are counted).
const QUOTED: usize = 16;

/// The subprotocol to answer with: the first of [`SUBPROTOCOLS`] the client offered.
pub fn choose(offered: &[String]) -> Option<&'static str> {
    SUBPROTOCOLS.into_iter().find(|p| offered.iter().any(|o| o == p))
}

/// A plain-text HTTP error reply (the connection closes after it).
pub fn refusal(status: StatusCode, text: String) -> ErrorResponse {
    let mut r = ErrorResponse::new(Some(format!("{text}\n")));
    *r.status_mut() = status;
    let h = r.headers_mut();
    h.insert("content-type", HeaderValue::from_static("text/plain; charset=utf-8"));
    h.insert("connection", HeaderValue::from_static("close"));
    if let Ok(len) = HeaderValue::from_str(&(text.len() + 1).to_string()) {
        h.insert("content-length", len);
    }
    r
}

/// The handshake callback: answers with the chosen subprotocol, or refuses with HTTP 400
/// naming what the client offered and what this server accepts. (The error is the HTTP
/// reply itself, as tungstenite's callback takes it.)
#[allow(clippy::result_large_err)]
pub fn negotiate(req: &Request, mut res: Response) -> Result<Response, ErrorResponse> {
    let offered = offered(req);
    match choose(&offered) {
        Some(p) => {
            res.headers_mut().insert("sec-websocket-protocol", HeaderValue::from_static(p));
            Ok(res)
        }
        None => {
            let got = if offered.is_empty() {
                "no subprotocol (no sec-websocket-protocol header)".to_owned()
            } else if offered.len() > QUOTED {
                format!("the subprotocol(s) {} and {} more", offered[..QUOTED].join(", "), offered.len() - QUOTED)
            } else {
                format!("the subprotocol(s) {}", offered.join(", "))
            };
            Err(refusal(
                StatusCode::BAD_REQUEST,
                format!(
                    "wmr-cli live view: the client offered {got}; this server speaks Foxglove's WebSocket protocol as {}",
                    SUBPROTOCOLS.join(" or ")
                ),
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn offers(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| (*s).to_owned()).collect()
    }

    #[test]
    fn either_name_is_accepted_and_the_sdk_name_preferred() {
        assert_eq!(choose(&offers(&["foxglove.websocket.v1"])), Some("foxglove.websocket.v1"));
        assert_eq!(choose(&offers(&["foxglove.sdk.v1"])), Some("foxglove.sdk.v1"));
        assert_eq!(choose(&offers(&["foxglove.websocket.v1", "foxglove.sdk.v1"])), Some("foxglove.sdk.v1"));
        // Exact names only: the schema-table protocol v1.1 is not this one.
        assert_eq!(choose(&offers(&["foxglove.sdk.v1.1"])), None);
        assert_eq!(choose(&offers(&[])), None);
    }

    /// Issue 39 item 6: the 17th offer was never looked at.
    #[test]
    fn every_offer_is_looked_at() {
        let mut req = Request::new(());
        let list: Vec<String> = (0..16).map(|i| format!("x{i}")).chain(["foxglove.sdk.v1".to_owned()]).collect();
        req.headers_mut().insert("sec-websocket-protocol", list.join(", ").parse().unwrap());
        let res = negotiate(&req, Response::new(())).expect("accepted");
        assert_eq!(res.headers()["sec-websocket-protocol"], "foxglove.sdk.v1");
    }
}
