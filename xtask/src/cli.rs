//! One argument parser for every command: each [`Command`] declares its flags (switches,
//! flags with a value, repeated flags) and whether it takes an `OUT_DIR`; its usage line
//! is written from that declaration, and anything else — an unknown flag, a missing or
//! attached-but-unwanted value, a second positional argument — is an error naming it,
//! followed by the usage. `--help` (or `-h`) prints the usage.
//!
//! [`lexopt`] splits the words (long flags, `--flag=value`, `-h`, `--` before positional
//! arguments); the declarations decide what they mean. Values are checked and converted
//! by each command ([`Args::parse_value`]), whose errors name the flag and value too.

use std::path::PathBuf;

use lexopt::Arg;

/// What a flag takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Takes {
    /// Nothing: present or not.
    Nothing,
    /// One value, at most once (`--size WxHxD`).
    Value(&'static str),
    /// One value, any number of times (`--obj PATH ...`).
    Values(&'static str),
}

/// A flag of a command, without its leading `--`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Flag {
    /// The name (`quick` for `--quick`).
    pub name: &'static str,
    /// What follows it.
    pub takes: Takes,
}

/// A switch: `--name`.
pub const fn switch(name: &'static str) -> Flag {
    Flag { name, takes: Takes::Nothing }
}

/// A flag with one value: `--name VALUE`.
pub const fn value(name: &'static str, placeholder: &'static str) -> Flag {
    Flag { name, takes: Takes::Value(placeholder) }
}

/// A flag that may be repeated: `--name VALUE ...`.
pub const fn repeated(name: &'static str, placeholder: &'static str) -> Flag {
    Flag { name, takes: Takes::Values(placeholder) }
}

/// What a command takes besides its flags.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Positional {
    /// Nothing.
    None,
    /// At most one `OUT_DIR`, defaulting to this path under the workspace root.
    OutDir(&'static str),
    /// Every word after the command, passed on unread (`bench`'s criterion arguments),
    /// shown as this placeholder.
    PassThrough(&'static str),
    /// A subject from a list, then an optional output folder (its default:
    /// `target/<command>/<subject>`): `bench-gpu culling [OUT_DIR]`.
    SubjectThenOutDir(&'static [&'static str]),
}

/// A command: its name, its arguments and what runs it.
pub struct Command {
    /// The name after `cargo xtask`.
    pub name: &'static str,
    /// Its flags, in usage order.
    pub flags: &'static [Flag],
    /// Pairs of flags that exclude each other (shown as `[--a A | --b B]`).
    pub exclusive: &'static [(&'static str, &'static str)],
    /// Its positional arguments.
    pub positional: Positional,
    /// Runs the parsed arguments.
    pub run: fn(&Args<'_>) -> Result<(), String>,
}

impl Command {
    /// The flag called `name`.
    fn flag(&self, name: &str) -> Option<&'static Flag> {
        self.flags.iter().find(|f| f.name == name)
    }

    /// `cargo xtask NAME [OUT_DIR] [--flag VALUE]...`, from the declaration.
    pub fn usage(&self) -> String {
        let mut words = vec!["cargo xtask".to_owned(), self.name.to_owned()];
        match self.positional {
            Positional::None => {}
            Positional::OutDir(_) => words.push("[OUT_DIR]".to_owned()),
            Positional::PassThrough(_) => {}
            Positional::SubjectThenOutDir(subjects) => {
                words.push(subjects.join("|"));
                words.push("[OUT_DIR]".to_owned());
            }
        }
        let shown = |flag: &Flag| match flag.takes {
            Takes::Nothing => format!("--{}", flag.name),
            Takes::Value(v) | Takes::Values(v) => format!("--{} {v}", flag.name),
        };
        for flag in self.flags {
            if self.exclusive.iter().any(|&(_, second)| second == flag.name) {
                continue;
            }
            let mut text = shown(flag);
            for &(_, second) in self.exclusive.iter().filter(|&&(first, _)| first == flag.name) {
                if let Some(other) = self.flag(second) {
                    text = format!("{text} | {}", shown(other));
                }
            }
            let repeat = if matches!(flag.takes, Takes::Values(_)) { "..." } else { "" };
            words.push(format!("[{text}]{repeat}"));
        }
        // Passed-through words follow the command's own flags.
        if let Positional::PassThrough(placeholder) = self.positional {
            words.push(format!("[{placeholder}]"));
        }
        words.join(" ")
    }

    /// `message` followed by the usage line: every parse error's form.
    pub fn error(&self, message: impl std::fmt::Display) -> String {
        format!("{}: {message}\nusage: {}", self.name, self.usage())
    }

    /// Parses the words after the command's name.
    pub fn parse(&self, words: &[String]) -> Result<Parsed<'_>, String> {
        let mut args = Args { command: self, subject: None, out_dir: None, values: Vec::new(), rest: Vec::new() };
        // A leading `--` only separates the arguments from the command (`cargo xtask
        // bench -- ARGS`); a later one ends the flags.
        let words = words.strip_prefix(&["--".to_owned()]).unwrap_or(words);
        if let Positional::PassThrough(_) = self.positional {
            if matches!(words, [only] if only == "--help" || only == "-h") {
                return Ok(Parsed::Help(self.usage()));
            }
            // The command's own flags come first; the first other word starts the rest.
            let mut rest = words;
            while let Some((first, after)) = rest.split_first() {
                let Some(long) = first.strip_prefix("--") else { break };
                let (name, attached) = long.split_once('=').map_or((long, None), |(n, v)| (n, Some(v.to_owned())));
                let Some(flag) = self.flag(name) else { break };
                rest = after;
                let value = self.value_of(name, flag, attached, || match rest.split_first() {
                    Some((v, tail)) if !looks_like_flag(v) => {
                        rest = tail;
                        Some(v.clone())
                    }
                    _ => None,
                })?;
                self.push_value(&mut args, flag, value)?;
            }
            self.check_exclusive(&args)?;
            args.rest = rest.to_vec();
            return Ok(Parsed::Run(args));
        }
        let mut parser = lexopt::Parser::from_args(words);
        loop {
            let arg = parser.next().map_err(|e| self.error(e))?;
            let name = match arg {
                None => break,
                Some(Arg::Long("help") | Arg::Short('h')) => return Ok(Parsed::Help(self.usage())),
                Some(Arg::Short(c)) => return Err(self.error(format!("unknown flag -{c}"))),
                Some(Arg::Long(name)) => name.to_owned(),
                Some(Arg::Value(word)) => {
                    let word = word.to_string_lossy().into_owned();
                    match (self.positional, &args.out_dir) {
                        (Positional::SubjectThenOutDir(subjects), _) if args.subject.is_none() => {
                            if !subjects.contains(&word.as_str()) {
                                return Err(
                                    self.error(format!("unknown subject `{word}` (known: {})", subjects.join(", ")))
                                );
                            }
                            args.subject = Some(word);
                        }
                        (Positional::OutDir(_) | Positional::SubjectThenOutDir(_), None) => {
                            args.out_dir = Some(PathBuf::from(word));
                        }
                        (Positional::OutDir(_) | Positional::SubjectThenOutDir(_), Some(first)) => {
                            return Err(self.error(format!(
                                "unexpected argument `{word}`: OUT_DIR is already `{}`",
                                first.display()
                            )));
                        }
                        _ => return Err(self.error(format!("unexpected argument `{word}`"))),
                    }
                    continue;
                }
            };
            let flag = self.flag(&name).ok_or_else(|| self.error(format!("unknown flag --{name}")))?;
            let attached = parser.optional_value().map(|v| v.to_string_lossy().into_owned());
            let value = self.value_of(&name, flag, attached, || {
                parser
                    .try_raw_args()?
                    .next_if(|next| !looks_like_flag(&next.to_string_lossy()))
                    .map(|v| v.to_string_lossy().into_owned())
            })?;
            self.push_value(&mut args, flag, value)?;
        }
        if let (Positional::SubjectThenOutDir(subjects), None) = (self.positional, &args.subject) {
            return Err(self.error(format!("needs a subject: {}", subjects.join(", "))));
        }
        self.check_exclusive(&args)?;
        Ok(Parsed::Run(args))
    }

    /// The value `--name` (declared as `flag`) takes, by the rules every command shares: a
    /// switch takes none (`--name=VALUE` is an error); a flag with a value takes the
    /// attached one (`--name=VALUE`, anything), else the next word (`next`, which takes
    /// it only when it does not look like a flag), else it is an error.
    fn value_of(
        &self,
        name: &str,
        flag: &Flag,
        attached: Option<String>,
        next: impl FnOnce() -> Option<String>,
    ) -> Result<String, String> {
        match (flag.takes, attached) {
            (Takes::Nothing, None) => Ok(String::new()),
            (Takes::Nothing, Some(v)) => Err(self.error(format!("--{name} takes no value (got `{v}`)"))),
            (_, Some(v)) => Ok(v),
            (Takes::Value(placeholder) | Takes::Values(placeholder), None) => {
                next().ok_or_else(|| self.error(format!("--{name} needs a value {placeholder}")))
            }
        }
    }

    /// Records `flag`'s value: an error when a flag that is not repeated comes twice.
    fn push_value(&self, args: &mut Args<'_>, flag: &'static Flag, value: String) -> Result<(), String> {
        if !matches!(flag.takes, Takes::Values(_)) && args.values.iter().any(|(n, _)| *n == flag.name) {
            return Err(self.error(format!("--{} given twice", flag.name)));
        }
        args.values.push((flag.name, value));
        Ok(())
    }

    /// An error when two flags that exclude each other are both given.
    fn check_exclusive(&self, args: &Args<'_>) -> Result<(), String> {
        match self.exclusive.iter().find(|&&(first, second)| args.flag(first) && args.flag(second)) {
            Some((first, second)) => Err(self.error(format!("--{first} and --{second} exclude each other"))),
            None => Ok(()),
        }
    }
}

/// Whether a word looks like a flag (`-x`, `--name`), and so is not a flag's value.
fn looks_like_flag(word: &str) -> bool {
    word.starts_with('-') && word.len() > 1
}

/// The outcome of [`Command::parse`].
pub enum Parsed<'c> {
    /// Run the command with these arguments.
    Run(Args<'c>),
    /// `--help`: print this usage.
    Help(String),
}

/// A command's parsed arguments.
pub struct Args<'c> {
    command: &'c Command,
    subject: Option<String>,
    out_dir: Option<PathBuf>,
    /// `(flag, value)` in the order given (the value empty for a switch).
    values: Vec<(&'static str, String)>,
    rest: Vec<String>,
}

impl Args<'_> {
    /// Whether `--name` was given.
    pub fn flag(&self, name: &str) -> bool {
        self.values.iter().any(|(n, _)| *n == name)
    }

    /// The values of `--name`, in the order given.
    pub fn values(&self, name: &str) -> Vec<&str> {
        self.values.iter().filter(|(n, _)| *n == name).map(|(_, v)| v.as_str()).collect()
    }

    /// The value of `--name`, if given.
    pub fn value(&self, name: &str) -> Option<&str> {
        self.values.iter().find(|(n, _)| *n == name).map(|(_, v)| v.as_str())
    }

    /// The value of `--name` converted by `convert`; its error becomes one naming the flag
    /// and the value, followed by the usage.
    pub fn parse_value<T>(&self, name: &str, convert: impl Fn(&str) -> Result<T, String>) -> Result<Option<T>, String> {
        self.value(name).map(|v| convert(v).map_err(|e| self.command.error(format!("--{name} {v}: {e}")))).transpose()
    }

    /// `message` followed by the command's usage, as every parse error reads.
    pub fn error(&self, message: impl std::fmt::Display) -> String {
        self.command.error(message)
    }

    /// The `OUT_DIR` given, else the command's default under the workspace root.
    pub fn out_dir(&self) -> PathBuf {
        match (&self.out_dir, self.command.positional) {
            (Some(dir), _) => dir.clone(),
            (None, Positional::OutDir(default)) => crate::workspace_root().join(default),
            (None, Positional::SubjectThenOutDir(_)) => {
                crate::workspace_root().join("target").join(self.command.name).join(self.subject())
            }
            (None, _) => crate::workspace_root(),
        }
    }

    /// The subject of a [`Positional::SubjectThenOutDir`] command (empty for others).
    pub fn subject(&self) -> &str {
        self.subject.as_deref().unwrap_or("")
    }

    /// The words passed through unread (a [`Positional::PassThrough`] command).
    pub fn rest(&self) -> &[String] {
        &self.rest
    }
}

/// A positive integer (of the type the caller asks for: `u32`, `u64`, …).
pub fn positive<T: std::str::FromStr + PartialOrd + Default>(text: &str) -> Result<T, String> {
    match text.parse::<T>() {
        Ok(n) if n > T::default() => Ok(n),
        _ => Err("expected a positive integer".to_owned()),
    }
}

/// An image size `WxH` of two positive integers.
pub fn resolution(text: &str) -> Result<(u32, u32), String> {
    let parts: Result<Vec<u32>, _> = text.split('x').map(str::parse).collect();
    match parts.as_deref() {
        Ok(&[w, h]) if w > 0 && h > 0 => Ok((w, h)),
        _ => Err("expected two positive sizes WxH".to_owned()),
    }
}

/// A tile size `WxHxD` of three positive integers.
pub fn grid_size(text: &str) -> Result<glam::UVec3, String> {
    let parts: Result<Vec<u32>, _> = text.split('x').map(str::parse).collect();
    match parts.as_deref() {
        Ok(&[x, y, z]) if x > 0 && y > 0 && z > 0 => Ok(glam::UVec3::new(x, y, z)),
        _ => Err("expected three positive sizes WxHxD".to_owned()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const QUICK: Flag = switch("quick");
    const SIZE: Flag = value("size", "WxHxD");
    const OBJ: Flag = repeated("obj", "PATH");
    const GRAIN: Flag = value("grain", "NAME");
    const TEST: Command = Command {
        name: "demo",
        flags: &[QUICK, OBJ, GRAIN, SIZE],
        exclusive: &[("obj", "grain")],
        positional: Positional::OutDir("target/demo"),
        run: |_| Ok(()),
    };

    fn words(text: &str) -> Vec<String> {
        text.split_whitespace().map(str::to_owned).collect()
    }

    fn run(text: &str) -> Result<Args<'static>, String> {
        match TEST.parse(&words(text))? {
            Parsed::Run(args) => Ok(args),
            Parsed::Help(_) => Err("help".to_owned()),
        }
    }

    #[test]
    fn the_usage_is_written_from_the_declaration() {
        assert_eq!(TEST.usage(), "cargo xtask demo [OUT_DIR] [--quick] [--obj PATH | --grain NAME]... [--size WxHxD]");
    }

    #[test]
    fn flags_values_and_the_out_dir_parse_in_any_order() {
        let args = run("--size 2x2x2 out --quick").unwrap();
        assert!(args.flag("quick") && !args.flag("obj"));
        assert_eq!((args.value("size"), args.out_dir()), (Some("2x2x2"), PathBuf::from("out")));
        let args = run("--size=1x1x1 --obj=a.obj --obj b.obj").unwrap();
        assert_eq!((args.value("size"), args.values("obj")), (Some("1x1x1"), vec!["a.obj", "b.obj"]));
        assert_eq!(args.out_dir(), crate::workspace_root().join("target/demo"));
        // A leading `--` is dropped; after a later one every word is positional.
        assert!(run("-- --quick").unwrap().flag("quick"));
        assert_eq!(run("--quick -- --odd").unwrap().out_dir(), PathBuf::from("--odd"));
    }

    #[test]
    fn every_mistake_names_itself_and_shows_the_usage() {
        for (text, expected) in [
            ("--obj", "--obj needs a value PATH"),
            ("--size --quick", "--size needs a value WxHxD"),
            ("--bogus", "unknown flag --bogus"),
            ("-x", "unknown flag -x"),
            ("a b", "unexpected argument `b`: OUT_DIR is already `a`"),
            ("--quick=yes", "--quick takes no value"),
            ("--size 1x1x1 --size 2x2x2", "--size given twice"),
            ("--obj a.obj --grain bean", "--obj and --grain exclude each other"),
        ] {
            let error = run(text).err().unwrap_or_else(|| panic!("`{text}` parsed"));
            assert!(error.starts_with(&format!("demo: {expected}")), "`{text}`: {error}");
            assert!(error.ends_with(&format!("\nusage: {}", TEST.usage())), "`{text}`: {error}");
        }
    }

    #[test]
    fn help_prints_the_usage() {
        for text in ["--help", "-h", "out --quick --help"] {
            assert!(matches!(TEST.parse(&words(text)), Ok(Parsed::Help(u)) if u == TEST.usage()), "{text}");
        }
    }

    #[test]
    fn values_are_converted_with_errors_naming_flag_and_value() {
        let args = run("--size 12").unwrap();
        let error = args.parse_value("size", |_| Err::<(), _>("expected WxHxD".to_owned())).unwrap_err();
        assert!(error.starts_with("demo: --size 12: expected WxHxD\nusage: "), "{error}");
        assert_eq!(args.parse_value("grain", |v| Ok(v.len())).unwrap(), None);
        assert_eq!(grid_size("12x8x4"), Ok(glam::UVec3::new(12, 8, 4)));
        for bad in ["12x12", "12x12x0", "1x2x3x4", "axbxc", "", "-1x2x3"] {
            assert!(grid_size(bad).is_err(), "{bad}");
        }
        assert_eq!(positive("3"), Ok(3));
        assert!(positive::<u32>("0").is_err() && positive::<u32>("-1").is_err() && positive::<u64>("x").is_err());
    }

    #[test]
    fn pass_through_commands_keep_every_word() {
        let bench = Command { positional: Positional::PassThrough("ARGS"), flags: &[], ..TEST };
        let parsed = bench.parse(&words("-- --save-baseline x --bogus")).unwrap();
        let Parsed::Run(args) = parsed else { panic!("help") };
        assert_eq!(args.rest(), words("--save-baseline x --bogus"));
        assert_eq!(bench.usage(), "cargo xtask demo [ARGS]");
    }

    #[test]
    fn pass_through_commands_read_their_own_flags_first() {
        const FLAGS: &[Flag] = &[value("save", "NAME"), switch("quick")];
        let bench = Command { positional: Positional::PassThrough("ARGS"), flags: FLAGS, exclusive: &[], ..TEST };
        let Ok(Parsed::Run(args)) = bench.parse(&words("--save=a --quick octahedral --save b")) else { panic!() };
        assert_eq!((args.value("save"), args.flag("quick")), (Some("a"), true));
        assert_eq!(args.rest(), words("octahedral --save b"));
        assert_eq!(bench.usage(), "cargo xtask demo [--save NAME] [--quick] [ARGS]");
        for (text, expected) in [
            ("--save", "--save needs a value NAME"),
            ("--save --quick", "--save needs a value NAME"),
            ("--quick=1", "--quick takes no value"),
            ("--save a --save b", "--save given twice"),
        ] {
            let error = bench.parse(&words(text)).err().unwrap_or_else(|| panic!("`{text}` parsed"));
            assert!(error.starts_with(&format!("demo: {expected}")), "`{text}`: {error}");
        }
    }
}
