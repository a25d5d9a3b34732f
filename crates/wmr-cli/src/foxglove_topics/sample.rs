//! The `wmr.Sample` message: a protobuf schema built from the CSV columns, and the encoding
//! written by hand so every message of a file has the same length.

use foxglove::Schema;
use prost::Message as _;
use prost_types::field_descriptor_proto::{Label, Type};
use prost_types::{DescriptorProto, FieldDescriptorProto, FileDescriptorProto, FileDescriptorSet};
use wmr_core::Sample;
use wmr_scenario::{MEASURED_COLUMNS, SAMPLE_COLUMNS, measured_values, sample_values};

/// Name of the sample schema.
pub const SAMPLE_SCHEMA: &str = "wmr.Sample";

/// The fields of `wmr.Sample`, in field-number order (1, 2, ...): the CSV columns after
/// `run`, then with a `[sensor]` the measured pose. Every field is a `double`.
pub fn sample_fields(measured: bool) -> Vec<&'static str> {
    let extra: &[&str] = if measured { &MEASURED_COLUMNS } else { &[] };
    SAMPLE_COLUMNS.iter().chain(extra).copied().collect()
}

/// `wmr.Sample` as a protobuf `FileDescriptorSet`: one `double` per field of
/// [`sample_fields`], numbered from 1. Units: s, m, rad, m/s, rad/s, N m (the CSV's).
pub(super) fn sample_schema(measured: bool) -> Schema {
    let field = sample_fields(measured)
        .into_iter()
        .enumerate()
        .map(|(i, name)| FieldDescriptorProto {
            name: Some(name.to_owned()),
            number: Some(i as i32 + 1),
            label: Some(Label::Optional as i32),
            r#type: Some(Type::Double as i32),
            json_name: Some(name.to_owned()),
            ..Default::default()
        })
        .collect();
    let file = FileDescriptorProto {
        name: Some("wmr/Sample.proto".into()),
        package: Some("wmr".into()),
        message_type: vec![DescriptorProto { name: Some("Sample".into()), field, ..Default::default() }],
        syntax: Some("proto3".into()),
        ..Default::default()
    };
    Schema::new(SAMPLE_SCHEMA, "protobuf", FileDescriptorSet { file: vec![file] }.encode_to_vec())
}

/// Appends a `wmr.Sample` message: every field written (field number, wire type 1, the
/// f64's 8 little-endian bytes), so every message of a file has the same length.
pub(super) fn encode_sample(s: &Sample<f64>, measured: bool, buf: &mut Vec<u8>) {
    let mut put = |number: u32, v: f64| {
        let mut key = (number << 3) | 1;
        while key >= 0x80 {
            buf.push((key as u8) | 0x80);
            key >>= 7;
        }
        buf.push(key as u8);
        buf.extend_from_slice(&v.to_le_bytes());
    };
    let mut n = 0;
    for v in sample_values(s) {
        n += 1;
        put(n, v);
    }
    if measured {
        for v in measured_values(s) {
            n += 1;
            put(n, v);
        }
    }
}
