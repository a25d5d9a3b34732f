//! A rosbag2 bag around a `--profile ros2` MCAP (`wmr-cli run ... --rosbag2`): the
//! `metadata.yaml` that `ros2 bag play DIR` and `ros2 bag info DIR` read beside the file.
//!
//! Written from the finished file's own summary section (its channels, schemas and
//! statistics), so the counts and times are those of the file as written. The format is
//! rosbag2's version 5 (Humble): `offered_qos_profiles` as one YAML string per topic, no
//! `type_description_hash`, `custom_data` or `ros_distro`. Humble reads only that form
//! (Jazzy's version 9 lists the profiles as a YAML sequence, which Humble's parser
//! refuses); Jazzy and later read every older version.

use std::fmt::Write as _;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

use super::topics::CDR;

/// The file name rosbag2 reads a bag's metadata from.
pub const METADATA_FILE: &str = "metadata.yaml";

/// rosbag2's metadata version written (Humble's; [module doc](self)).
pub const METADATA_VERSION: u32 = 5;

/// Length of an MCAP footer record: opcode (1), length (8), summary_start (8),
/// summary_offset_start (8), summary_crc (4).
const FOOTER_RECORD_LEN: u64 = 29;
/// Length of the MCAP magic at the file's end.
const MAGIC_LEN: u64 = 8;
/// A summary section larger than this is not one wmr writes (its chunk indexes grow about
/// 100 bytes per chunk): refused rather than read into memory.
const MAX_SUMMARY_BYTES: u64 = 256 << 20;

/// One topic of the bag, as `topics_with_message_count` lists it.
#[derive(Clone, Debug, PartialEq)]
pub struct BagTopic {
    /// The topic name (`/tf`, `/run3/odom`).
    pub name: String,
    /// The ROS 2 type (`tf2_msgs/msg/TFMessage`).
    pub msg_type: String,
    /// The channel's `offered_qos_profiles` (a YAML string).
    pub offered_qos_profiles: String,
    /// Messages on the topic.
    pub message_count: u64,
}

/// What `metadata.yaml` says of one MCAP file.
#[derive(Clone, Debug, PartialEq)]
pub struct BagInfo {
    /// The MCAP's file name, relative to the bag's folder.
    pub file_name: String,
    /// The earliest message's log time, ns.
    pub starting_time_ns: u64,
    /// From the earliest to the latest message's log time, ns.
    pub duration_ns: u64,
    /// Messages in all.
    pub message_count: u64,
    /// The file's CDR channels, in channel id order.
    pub topics: Vec<BagTopic>,
}

/// The path of the `metadata.yaml` beside `mcap`.
pub fn metadata_path(mcap: &Path) -> PathBuf {
    crate::atomic::parent_dir(mcap).join(METADATA_FILE)
}

/// Reads the summary of the finished MCAP at `path`: its CDR channels and statistics. A
/// file with another channel encoding (a `--profile both` file) is refused: `ros2 bag
/// play` cannot decode its Foxglove channels.
pub fn read_info(path: &Path) -> Result<BagInfo> {
    let shown = wmr_scenario::shown(path);
    let mut file = File::open(path).with_context(|| format!("cannot read {shown}"))?;
    let len = file.metadata().with_context(|| format!("cannot read {shown}"))?.len();
    if len < FOOTER_RECORD_LEN + MAGIC_LEN {
        bail!("{shown} is too short to be an MCAP file");
    }
    let mut footer = [0u8; (FOOTER_RECORD_LEN + MAGIC_LEN) as usize];
    file.seek(SeekFrom::Start(len - footer.len() as u64))?;
    file.read_exact(&mut footer).with_context(|| format!("cannot read {shown}"))?;
    let word = |at: usize| u64::from_le_bytes(footer[at..at + 8].try_into().expect("8 bytes"));
    // Footer: opcode 0x02, record length 20, summary_start, summary_offset_start, crc.
    if footer[0] != 0x02 || word(1) != FOOTER_RECORD_LEN - 9 {
        bail!("{shown} has no MCAP footer");
    }
    let (summary_start, summary_offset_start) = (word(9), word(17));
    let footer_start = len - FOOTER_RECORD_LEN - MAGIC_LEN;
    let summary_end = if summary_offset_start == 0 { footer_start } else { summary_offset_start };
    if summary_start == 0 || summary_start > summary_end || summary_end > footer_start {
        bail!("{shown} has no MCAP summary section");
    }
    if summary_end - summary_start > MAX_SUMMARY_BYTES {
        bail!("{shown}'s MCAP summary section is over {MAX_SUMMARY_BYTES} bytes");
    }
    let mut summary = vec![0u8; (summary_end - summary_start) as usize];
    file.seek(SeekFrom::Start(summary_start))?;
    file.read_exact(&mut summary).with_context(|| format!("cannot read {shown}"))?;
    info_of_summary(&summary, path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default())
        .with_context(|| format!("cannot read the summary of {shown}"))
}

/// [`BagInfo`] from an MCAP summary section's records.
fn info_of_summary(summary: &[u8], file_name: String) -> Result<BagInfo> {
    use mcap::records::Record;
    let mut schemas = std::collections::BTreeMap::new();
    let mut channels = Vec::new();
    let mut stats = None;
    for record in mcap::read::LinearReader::sans_magic(summary) {
        match record? {
            Record::Schema { header, .. } => {
                schemas.insert(header.id, header.name);
            }
            Record::Channel(c) => channels.push(c),
            Record::Statistics(s) => stats = Some(s),
            _ => {}
        }
    }
    let Some(stats) = stats else { bail!("no statistics record") };
    channels.sort_by_key(|c| c.id);
    let mut topics = Vec::with_capacity(channels.len());
    for c in channels {
        if c.message_encoding != CDR {
            bail!(
                "channel {} is {} (a --profile both file): a rosbag2 bag holds ROS 2 (cdr) channels only",
                c.topic,
                c.message_encoding
            );
        }
        let Some(msg_type) = schemas.get(&c.schema_id) else { bail!("channel {} has no schema", c.topic) };
        topics.push(BagTopic {
            name: c.topic.clone(),
            msg_type: msg_type.clone(),
            offered_qos_profiles: c.metadata.get("offered_qos_profiles").cloned().unwrap_or_default(),
            message_count: stats.channel_message_counts.get(&c.id).copied().unwrap_or(0),
        });
    }
    let (start, end) = if stats.message_count == 0 {
        (0, 0)
    } else {
        (stats.message_start_time, stats.message_end_time.max(stats.message_start_time))
    };
    Ok(BagInfo {
        file_name,
        starting_time_ns: start,
        duration_ns: end - start,
        message_count: stats.message_count,
        topics,
    })
}

/// `s` as a double-quoted YAML scalar (escapes `\`, `"` and control characters).
fn quoted(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for ch in s.chars() {
        match ch {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04x}", u32::from(c));
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The `metadata.yaml` text of a bag of the one file `info` describes.
pub fn metadata_yaml(info: &BagInfo) -> String {
    let mut y = String::new();
    let _ = writeln!(y, "rosbag2_bagfile_information:");
    let _ = writeln!(y, "  version: {METADATA_VERSION}");
    let _ = writeln!(y, "  storage_identifier: mcap");
    let _ = writeln!(y, "  duration:\n    nanoseconds: {}", info.duration_ns);
    let _ = writeln!(y, "  starting_time:\n    nanoseconds_since_epoch: {}", info.starting_time_ns);
    let _ = writeln!(y, "  message_count: {}", info.message_count);
    let _ = writeln!(y, "  topics_with_message_count:");
    for t in &info.topics {
        let _ = writeln!(y, "    - topic_metadata:");
        let _ = writeln!(y, "        name: {}", quoted(&t.name));
        let _ = writeln!(y, "        type: {}", quoted(&t.msg_type));
        let _ = writeln!(y, "        serialization_format: {CDR}");
        let _ = writeln!(y, "        offered_qos_profiles: {}", quoted(&t.offered_qos_profiles));
        let _ = writeln!(y, "      message_count: {}", t.message_count);
    }
    let _ = writeln!(y, "  compression_format: \"\"");
    let _ = writeln!(y, "  compression_mode: \"\"");
    let _ = writeln!(y, "  relative_file_paths:\n    - {}", quoted(&info.file_name));
    let _ = writeln!(y, "  files:");
    let _ = writeln!(y, "    - path: {}", quoted(&info.file_name));
    let _ = writeln!(y, "      starting_time:\n        nanoseconds_since_epoch: {}", info.starting_time_ns);
    let _ = writeln!(y, "      duration:\n        nanoseconds: {}", info.duration_ns);
    let _ = writeln!(y, "      message_count: {}", info.message_count);
    y
}

/// Writes the `metadata.yaml` beside the finished MCAP at `mcap` (replaced atomically);
/// returns its path.
pub fn write_metadata(mcap: &Path) -> Result<PathBuf> {
    let info = read_info(mcap)?;
    let path = metadata_path(mcap);
    crate::foxglove_cmd::write_text(&path, &metadata_yaml(&info))?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoting_keeps_yaml_scalars_intact() {
        assert_eq!(quoted("/tf"), "\"/tf\"");
        assert_eq!(quoted("- a: 1\n  b: \"x\\y\""), "\"- a: 1\\n  b: \\\"x\\\\y\\\"\"");
        assert_eq!(quoted("\u{1}"), "\"\\u0001\"");
    }

    #[test]
    fn an_empty_file_lists_no_time() {
        let info = BagInfo {
            file_name: "run.mcap".into(),
            starting_time_ns: 0,
            duration_ns: 0,
            message_count: 0,
            topics: vec![],
        };
        let y = metadata_yaml(&info);
        assert!(y.contains("  message_count: 0\n") && y.contains("    - \"run.mcap\"\n"), "{y}");
    }
}
