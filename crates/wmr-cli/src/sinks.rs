//! The output formats of `run -o OUT`, one line each in the `sinks!` list below: a new
//! format is its own file (a [`Sink`] with a [`FileSink`] impl: its name, which is also
//! its file extension, its one-line help, its bytes per sample and how it opens) plus one
//! line there. `--format`'s values and help, telling the format from OUT's extension, the
//! free-space check and the sink `run` writes to all follow from the list.

use wmr_scenario::{Scenario, Sink, SinkError};

use crate::atomic::OutWriter;
use crate::mcap_sink::Profile;
use crate::{csv_sink, mcap_sink};

/// What `run` passes a sink besides the scenario: the options of its command line.
#[derive(Clone, Copy, Debug, Default)]
pub struct SinkOptions {
    /// `--profile`: the MCAP's topics (only MCAP reads it; `run` refuses it for the others).
    pub profile: Profile,
}

/// A sink that writes one output file of runs.
pub trait FileSink: Sink + Sized + 'static {
    /// Its `--format` value and its file extension (lower case, without the dot).
    const NAME: &'static str;
    /// One line for `--format`'s help.
    const HELP: &'static str;
    /// Output bytes per logged sample: (below which no moving robot writes, typical).
    /// The free-space check refuses only work that surely cannot fit, on the first figure.
    const BYTES_PER_SAMPLE: (u64, u64);

    /// Starts the output on `out` for the runs of `scenario` (a header, a file's
    /// preamble), so that an output that cannot be written fails before any run starts.
    fn open(out: OutWriter, scenario: &Scenario, options: &SinkOptions) -> Result<Self, SinkError>;
}

/// Defines [`Format`], one variant per sink, and what follows from the list.
macro_rules! sinks {
    ($( $variant:ident => $ty:ty; )+) => {
        /// Output format of `run -o OUT` (`--format`, else OUT's extension).
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum Format {
            $( #[doc = concat!("[`", stringify!($ty), "`].")] $variant, )+
        }

        impl Format {
            /// Every format, in `--format`'s order.
            pub const ALL: &'static [Format] = &[$(Format::$variant),+];

            /// The `--format` value, which is also the file extension.
            pub fn name(self) -> &'static str {
                match self { $( Format::$variant => <$ty as FileSink>::NAME, )+ }
            }

            /// [`FileSink::HELP`].
            pub fn help(self) -> &'static str {
                match self { $( Format::$variant => <$ty as FileSink>::HELP, )+ }
            }

            /// [`FileSink::BYTES_PER_SAMPLE`].
            pub fn bytes_per_sample(self) -> (u64, u64) {
                match self { $( Format::$variant => <$ty as FileSink>::BYTES_PER_SAMPLE, )+ }
            }

            /// Opens the sink of this format on `out` ([`FileSink::open`]).
            pub fn open(
                self,
                out: OutWriter,
                scenario: &Scenario,
                options: &SinkOptions,
            ) -> Result<Box<dyn Sink>, SinkError> {
                Ok(match self {
                    $( Format::$variant => Box::new(<$ty as FileSink>::open(out, scenario, options)?), )+
                })
            }
        }
    };
}

sinks! {
    Mcap => mcap_sink::McapSink;
    Csv => csv_sink::CsvSink;
}

impl Format {
    /// The format whose name is `extension` (any case), if any.
    pub fn of_extension(extension: &str) -> Option<Format> {
        Format::ALL.iter().copied().find(|f| extension.eq_ignore_ascii_case(f.name()))
    }

    /// `.mcap or .csv`: the extensions, for messages.
    pub fn extensions() -> String {
        let names: Vec<String> = Format::ALL.iter().map(|f| format!(".{}", f.name())).collect();
        match names.split_last() {
            Some((last, [])) => last.clone(),
            Some((last, init)) => format!("{} or {last}", init.join(", ")),
            None => String::new(),
        }
    }
}

/// `--format`'s values: the names, with each sink's help.
impl clap::ValueEnum for Format {
    fn value_variants<'a>() -> &'a [Self] {
        Format::ALL
    }

    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        Some(clap::builder::PossibleValue::new(self.name()).help(self.help()))
    }
}

#[cfg(test)]
mod tests {
    use super::Format;
    use clap::ValueEnum as _;

    /// Every format is told from its own extension, in any case, and `--format` parses
    /// its name: the list, the extensions and the values are one.
    #[test]
    fn each_format_is_its_extension_and_its_value() {
        let mut names: Vec<&str> = Format::ALL.iter().map(|f| f.name()).collect();
        for &f in Format::ALL {
            assert_eq!(Format::of_extension(f.name()), Some(f));
            assert_eq!(Format::of_extension(&f.name().to_ascii_uppercase()), Some(f));
            assert_eq!(Format::from_str(f.name(), false), Ok(f));
            assert!(!f.help().is_empty(), "{} has no help", f.name());
            let (least, typical) = f.bytes_per_sample();
            assert!(0 < least && least <= typical, "{}: {least} > {typical}", f.name());
        }
        assert_eq!(Format::of_extension("txt"), None);
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), Format::ALL.len(), "two formats share a name");
        assert_eq!(Format::extensions(), ".mcap or .csv");
    }
}
