//! Foxglove's WebSocket protocol, server side, as far as `--live` speaks it: the subprotocol
//! names, the JSON messages (serverInfo, advertise, status) and binary frames (message
//! data, time) the server sends, and the client operations it understands (subscribe,
//! unsubscribe). Spec: foxglove/ws-protocol `docs/spec.md` (v1); `foxglove.sdk.v1` is the
//! same protocol as `foxglove.websocket.v1` under the SDK's name.

use base64::Engine as _;
use serde_json::{Value, json};

/// The subprotocols accepted, in the server's order of preference when a client offers
/// several.
pub const SUBPROTOCOLS: [&str; 2] = ["foxglove.sdk.v1", "foxglove.websocket.v1"];

/// Binary opcode of a message on a subscription: `[1][subscription id u32 LE][log time ns
/// u64 LE][payload]`.
const OP_MESSAGE_DATA: u8 = 1;
/// Binary opcode of the server clock: `[2][time ns u64 LE]`.
const OP_TIME: u8 = 2;

/// A channel the server advertises.
pub struct ChannelInfo {
    /// The channel id, unique on the server.
    pub id: u64,
    /// `/runN/KIND`.
    pub topic: String,
    /// Message encoding (`protobuf`).
    pub encoding: String,
    /// Schema name, e.g. `foxglove.FrameTransform`.
    pub schema_name: String,
    /// Schema encoding (`protobuf`): the schema bytes go out base64-encoded.
    pub schema_encoding: String,
    /// The schema (a protobuf `FileDescriptorSet`).
    pub schema: Vec<u8>,
}

/// The `serverInfo` message: the server's name and the `time` capability (the server clock
/// is the simulation time).
pub fn server_info(name: &str) -> String {
    json!({ "op": "serverInfo", "name": name, "capabilities": ["time"], "supportedEncodings": [], "metadata": {} })
        .to_string()
}

/// The `advertise` message of every channel.
pub fn advertise(channels: &[ChannelInfo]) -> String {
    let list: Vec<Value> = channels
        .iter()
        .map(|c| {
            json!({
                "id": c.id,
                "topic": c.topic,
                "encoding": c.encoding,
                "schemaName": c.schema_name,
                "schema": base64::engine::general_purpose::STANDARD.encode(&c.schema),
                "schemaEncoding": c.schema_encoding,
            })
        })
        .collect();
    json!({ "op": "advertise", "channels": list }).to_string()
}

/// Status levels of a `status` message.
#[derive(Clone, Copy)]
pub enum Level {
    /// 1.
    Warning = 1,
    /// 2.
    Error = 2,
}

/// A `status` message shown to the client's user.
pub fn status(level: Level, message: &str) -> String {
    json!({ "op": "status", "level": level as u8, "message": message }).to_string()
}

/// A message-data frame for `subscription` at `log_time_ns`.
pub fn message_data(subscription: u32, log_time_ns: u64, payload: &[u8]) -> Vec<u8> {
    let mut b = Vec::with_capacity(13 + payload.len());
    b.push(OP_MESSAGE_DATA);
    b.extend_from_slice(&subscription.to_le_bytes());
    b.extend_from_slice(&log_time_ns.to_le_bytes());
    b.extend_from_slice(payload);
    b
}

/// A time frame: the server clock at `time_ns`.
pub fn time(time_ns: u64) -> Vec<u8> {
    let mut b = Vec::with_capacity(9);
    b.push(OP_TIME);
    b.extend_from_slice(&time_ns.to_le_bytes());
    b
}

/// What a client asked, from one text message.
#[derive(Debug, PartialEq)]
pub enum Request {
    /// `subscribe`: (subscription id, channel id) pairs.
    Subscribe(Vec<(u32, u64)>),
    /// `unsubscribe`: subscription ids.
    Unsubscribe(Vec<u32>),
    /// An operation this server does not offer (named), answered with a warning.
    Unsupported(String),
}

/// Parses a client's text message; `Err` says what is wrong with it (for a status reply).
pub fn parse_request(text: &str) -> Result<Request, String> {
    let v: Value = serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
    let op = v.get("op").and_then(Value::as_str).ok_or("no \"op\" string")?;
    let u32_of = |x: &Value, what: &str| -> Result<u32, String> {
        x.as_u64().and_then(|n| u32::try_from(n).ok()).ok_or_else(|| format!("{op}: {what} must be an integer 0..2^32"))
    };
    match op {
        "subscribe" => {
            let subs =
                v.get("subscriptions").and_then(Value::as_array).ok_or("subscribe: no \"subscriptions\" array")?;
            let mut out = Vec::with_capacity(subs.len());
            for s in subs {
                let id = u32_of(s.get("id").unwrap_or(&Value::Null), "id")?;
                let channel = s
                    .get("channelId")
                    .and_then(Value::as_u64)
                    .ok_or("subscribe: channelId must be a non-negative integer")?;
                out.push((id, channel));
            }
            Ok(Request::Subscribe(out))
        }
        "unsubscribe" => {
            let ids = v
                .get("subscriptionIds")
                .and_then(Value::as_array)
                .ok_or("unsubscribe: no \"subscriptionIds\" array")?;
            ids.iter().map(|x| u32_of(x, "subscriptionIds")).collect::<Result<_, _>>().map(Request::Unsubscribe)
        }
        other => Ok(Request::Unsupported(other.chars().take(64).collect())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_follow_the_spec_layout() {
        let f = message_data(7, 0x0102_0304_0506_0708, b"ab");
        assert_eq!(f, [1, 7, 0, 0, 0, 8, 7, 6, 5, 4, 3, 2, 1, b'a', b'b']);
        assert_eq!(time(1), [2, 1, 0, 0, 0, 0, 0, 0, 0]);
    }

    #[test]
    fn requests_parse_and_bad_ones_say_why() {
        let s = r#"{"op":"subscribe","subscriptions":[{"id":1,"channelId":4},{"id":2,"channelId":0}]}"#;
        assert_eq!(parse_request(s), Ok(Request::Subscribe(vec![(1, 4), (2, 0)])));
        assert_eq!(parse_request(r#"{"op":"unsubscribe","subscriptionIds":[1]}"#), Ok(Request::Unsubscribe(vec![1])));
        assert_eq!(parse_request(r#"{"op":"getParameters"}"#), Ok(Request::Unsupported("getParameters".into())));
        assert!(parse_request("{").unwrap_err().contains("not JSON"));
        assert!(parse_request(r#"{"op":"subscribe","subscriptions":[{"id":-1,"channelId":0}]}"#).is_err());
        assert!(parse_request(r#"{"op":"subscribe","subscriptions":[{"id":4294967296,"channelId":0}]}"#).is_err());
        assert!(parse_request("[]").is_err());
    }
}
