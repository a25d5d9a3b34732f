//! The `wmr.Sample` message: a protobuf schema built from the CSV columns, and the encoding
//! written by hand so every message of a file has the same length.

use foxglove::Schema;
use prost::Message as _;
use prost_types::field_descriptor_proto::{Label, Type};
use prost_types::{DescriptorProto, FieldDescriptorProto, FileDescriptorProto, FileDescriptorSet};
use wmr_core::Sample;
use wmr_scenario::Columns;

/// Name of the sample schema.
pub const SAMPLE_SCHEMA: &str = "wmr.Sample";

/// `wmr.Sample` as a protobuf `FileDescriptorSet`: one `double` per column of `columns`
/// (the CSV's after `run`, in its order), numbered from 1. Units: the CSV's.
pub(super) fn sample_schema(columns: &Columns) -> Schema {
    let field = columns
        .names()
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

/// Appends a `wmr.Sample` message of `columns`: every field written (field number, wire
/// type 1, the f64's 8 little-endian bytes), so every message of a file has the same length.
pub(super) fn encode_sample(s: &Sample<f64>, columns: &Columns, buf: &mut Vec<u8>) {
    for (i, v) in columns.values(s).enumerate() {
        let mut key = ((i as u32 + 1) << 3) | 1;
        while key >= 0x80 {
            buf.push((key as u8) | 0x80);
            key >>= 7;
        }
        buf.push(key as u8);
        buf.extend_from_slice(&v.to_le_bytes());
    }
}
