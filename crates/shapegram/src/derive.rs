//! `shapegram derive`: a grammar applied to lots, written as a model file.

use std::collections::HashMap;
use std::io::IsTerminal;
use std::sync::Arc;
use std::time::{Duration, Instant};

use serde::Serialize;
use serde::ser::SerializeMap;
use shapegram_eval::{
    Derivation, DeriveError, DeriveOptions, InitialShape, MetadataScope, ModelOptions, Program,
    Value,
};
use shapegram_export::tiles::TileGrid;
use shapegram_export::{ExportOptions, Format};
use shapegram_geom::Model;
use shapegram_syntax::SourceFile;

use crate::cli::DeriveArgs;
use crate::progress::with_spinner;
use crate::{Failure, counted, grammar, lots, print_stdout, resolve, tiles};

/// Derives, writes and reports.
pub fn run(args: &DeriveArgs) -> Result<(), Failure> {
    // Cheap checks first, so that a typo fails before any work.
    if let Some(output) = &args.output {
        Format::from_path(output)?;
    }
    let placing = lots::Placing {
        crs: args.crs,
        recentre: args.tiles.is_some(),
    };
    let lots::Collected {
        lots,
        warnings: lot_warnings,
        frame,
    } = lots::collect(&args.lot, &args.lots, placing)?;
    if !args.quiet {
        for warning in &lot_warnings {
            eprintln!("warning: {warning}");
        }
    }
    let input = grammar::open(&args.grammar, args.rule_file.as_deref(), !args.quiet)?;
    let source = input.source.clone();
    let goal = grammar::is_goal_grammar(&source, args.dialect.dialect());
    check_goal_options(&source, goal, args)?;
    // A tiled city that nothing else reads whole derives cell by cell (docs/tiles.md).
    let streamed = args.tiles.is_some()
        && !goal
        && args.output.is_none()
        && !args.stats
        && args.at_node.is_none();
    if args.shard.is_some() && !streamed {
        return Err(Failure::usage(
            "--shard writes one shard's tiles only: it does not go with -o, --stats, \
             --at-node or goal grammars",
        ));
    }
    let glb = match &args.output {
        Some(output) => matches!(Format::from_path(output)?, Format::Glb),
        None => false,
    };
    if let Some(warning) = unwritten_metadata(args, glb).filter(|_| !args.quiet) {
        eprintln!("warning: {warning}");
    }
    // Goal grammars start from their axioms: lots only when asked for.
    let lots = if goal && args.lot.is_empty() && args.lots.is_empty() {
        Vec::new()
    } else {
        lots
    };

    let options = DeriveOptions {
        seed: args.seed,
        attrs: args
            .attr
            .iter()
            .map(|(name, value)| (name.clone(), Value::parse_literal(value)))
            .collect(),
        start_rule: args.start.clone(),
        max_shapes: args.max_shapes,
        max_depth: args.max_depth,
        time_budget: (args.timeout > 0.0).then(|| Duration::from_secs_f64(args.timeout)),
        generations: args.generations,
        assets: Some(Arc::new(input.assets(args.missing_assets.into()))),
        // The tree is what a state at a node is made from, and where leaves' metadata comes
        // from.
        keep_tree: args.at_node.is_some() || (args.metadata && (glb || args.tiles.is_some())),
        implicit_cell: args.implicit_cell,
        trace: false,
        max_steps: args.max_steps,
        control: None,
    };

    let started = Instant::now();
    let spinner = !args.quiet && std::io::stderr().is_terminal();
    let label = format!("deriving {}", source.name());
    let derive = |program: &Program, sources: &[SourceFile]| {
        shapegram_eval::derive(program, &lots, &options).map_err(|e| derive_failure(sources, &e))
    };
    let derived = if goal {
        // Goal grammars: with their library, and with a repository when asked or locked.
        let plan = resolve::plan(args)?;
        let local = grammar::read_library(source, &args.grammar, &args.library, !args.quiet)?;
        let library = resolve::Library {
            local,
            args,
            derive: &derive,
        };
        with_spinner(spinner, &label, || resolve::derive(&library, plan))?
    } else {
        let dialect = args.dialect.dialect();
        let compiled = match &args.style {
            Some(style) => grammar::compile_style(&input, !args.quiet, dialect, style)?,
            None => grammar::compile(&input, !args.quiet, dialect),
        };
        let (program, sources) = compiled.into_program()?;
        if streamed {
            let run = Tiled {
                args,
                program: &program,
                sources: &sources,
                options: &options,
            };
            return with_spinner(spinner, &label, || run.write(&lots, frame, started));
        }
        let derivation = with_spinner(spinner, &label, || derive(&program, &sources))?;
        resolve::Derived {
            program,
            sources,
            derivation,
            report: None,
        }
    };
    let derive_time = started.elapsed();
    let resolve::Derived {
        program,
        sources,
        derivation,
        report,
    } = derived;
    let source = &sources[0];
    print_prints(&derivation, |_| true);

    let export_started = Instant::now();
    if let Some(dir) = &args.tiles {
        let grid = TileGrid {
            size: args.tile_size,
        };
        let names: Vec<String> = program.attr_names().map(str::to_owned).collect();
        let metadata = args.metadata.then_some(&names[..]);
        let encoding = args.glb.encoding();
        let summary = tiles::write(
            &derivation,
            &lots,
            frame,
            dir,
            grid,
            metadata,
            encoding,
            args.quiet,
        )?;
        if !args.quiet {
            eprintln!("wrote {}", tiles::described(dir, &summary));
        }
    }
    // The whole model only when something reads it (an output file, the stats, a pose checked
    // against its joints): a tiled city is written tile by tile, and a run without any of those
    // needs only to know whether the model would be empty.
    let whole = args.output.is_some() || args.stats || args.pose.is_some();
    let model_options = ModelOptions {
        instances: args.instancing.candidates(glb),
        smaller_only: args.instancing == crate::cli::InstancingArg::Auto,
        metadata: match (args.metadata && glb, args.group) {
            (false, _) => MetadataScope::None,
            (true, false) => MetadataScope::Leaf,
            (true, true) => MetadataScope::Part,
        },
        attr_names: program.attr_names().map(str::to_owned).collect(),
    };
    let mut model = match args.at_node {
        Some(node) => derivation
            .model_at_node(node)
            .map_err(|e| Failure::new(e.message).with_hints(e.hints))?,
        None if whole => derivation.to_model_with(&model_options),
        None => Model::default(),
    };
    if let Some(pose) = &args.pose {
        crate::pose::apply(pose, &mut model)?;
    }
    let named_poses = program.named_poses();
    if glb && !named_poses.is_empty() {
        add_named_poses(
            &program,
            &lots,
            &options,
            &named_poses,
            &sources,
            &mut model,
        )?;
    }
    if args.merge_locked {
        model = model.with_free_joints_only();
    }
    if let Some(output) = &args.output {
        let options = ExportOptions {
            group_by_part: args.group,
            instancing: args.instancing.into(),
            ..ExportOptions::default()
        };
        let options = args.glb.apply(options, output, args.quiet);
        shapegram_export::save(&model, output, &options)?;
    }
    let export_time = export_started.elapsed();

    if !args.quiet {
        let empty = if whole || args.at_node.is_some() {
            model.parts.iter().all(|p| p.mesh.is_empty())
        } else {
            args.tiles.is_none() && !derivation.has_geometry()
        };
        if empty {
            eprintln!("warning: the model is empty: no leaf has geometry");
        }
        let mut target = match &args.output {
            Some(output) => output.display().to_string(),
            None => format!("{} (no output file)", source.name()),
        };
        if let Some(node) = args.at_node {
            target.push_str(&format!(" at node {node} of {}", derivation.tree.len()));
        }
        let stats = &derivation.stats;
        let starts = if stats.grammars.is_empty() {
            counted(lots.len(), "lot", "lots")
        } else {
            let used = stats.grammars.iter().filter(|(_, n)| *n > 0).count();
            format!(
                "{} from {} of {}",
                counted(stats.steps, "step", "steps"),
                counted(used, "grammar", "grammars"),
                stats.grammars.len()
            )
        };
        if let Some(report) = &report {
            eprint!("{}", report.summary());
        }
        eprintln!(
            "derived {target}: {starts}, {}, {}, {}",
            counted(stats.shapes, "shape", "shapes"),
            counted(stats.leaves, "leaf", "leaves"),
            duration(derive_time + export_time)
        );
    }
    if args.stats {
        let mut json = StatsJson::new(
            source.name(),
            lots.len(),
            args.seed,
            &derivation,
            &model,
            derive_time,
            export_time,
        );
        json.named_poses = named_poses.into_iter().map(|(name, _)| name).collect();
        json.at_node = args.at_node;
        json.repository = report;
        let mut text = serde_json::to_string(&json)
            .map_err(|e| Failure::new(format!("cannot render JSON: {e}")))?;
        text.push('\n');
        print_stdout(&text)?;
    }
    Ok(())
}

/// A tiled run derived cell by cell: what it derives with.
struct Tiled<'a> {
    args: &'a DeriveArgs,
    program: &'a Program,
    sources: &'a [SourceFile],
    options: &'a DeriveOptions,
}

impl Tiled<'_> {
    /// Derives `lots` cell by cell into the tileset, printing the grammar's `print` output
    /// as each cell's derivation ends, and reports.
    fn write(
        &self,
        lots: &[InitialShape],
        frame: lots::Frame,
        started: Instant,
    ) -> Result<(), Failure> {
        let args = self.args;
        let dir = args.tiles.as_deref().expect("tiled runs have --tiles");
        let tiling = tiles::Tiling {
            grid: TileGrid {
                size: args.tile_size,
            },
            halo: self.program.has_context_rules().then_some(args.halo),
            shard: args.shard,
            metadata: args
                .metadata
                .then(|| self.program.attr_names().map(str::to_owned).collect()),
            encoding: args.glb.encoding(),
        };
        let derive = |cell: &[InitialShape], own: &[bool]| {
            let derivation = shapegram_eval::derive(self.program, cell, self.options)
                .map_err(|e| derive_failure(self.sources, &e))?;
            print_prints(&derivation, |lot| own[lot as usize]);
            Ok(derivation)
        };
        let tiled = tiles::stream::<Failure>(lots, frame, dir, tiling, derive, args.quiet)?;
        if args.quiet {
            return Ok(());
        }
        match args.shard {
            Some(shard) => eprintln!(
                "wrote {} (shard {shard}): {}, {} of {}{}",
                dir.join(shard.file_name()).display(),
                counted(tiled.summary.near, "near tile", "near tiles"),
                counted(tiled.summary.far, "far tile", "far tiles"),
                counted(tiled.summary.lots, "lot", "lots"),
                if tiled.summary.far == 0 {
                    " (the city has fewer parent tiles than shards)"
                } else {
                    ""
                }
            ),
            None => eprintln!("wrote {}", tiles::described(dir, &tiled.summary)),
        }
        eprintln!(
            "derived {} (no output file): {}, {} cell by cell, {}, {}, {}",
            self.sources[0].name(),
            counted(lots.len(), "lot", "lots"),
            counted(tiled.derived, "lot derived", "lots derived"),
            counted(tiled.shapes, "shape", "shapes"),
            counted(tiled.leaves, "leaf", "leaves"),
            duration(started.elapsed())
        );
        Ok(())
    }
}

/// Prints the `print` output of a derivation on stderr, a `print: ` line each, of the lots
/// `printed` takes.
fn print_prints(derivation: &Derivation, printed: impl Fn(u32) -> bool) {
    let mut prints = String::new();
    let lines = derivation.prints.iter().zip(&derivation.print_lots);
    for (text, _) in lines.filter(|&(_, &lot)| printed(lot)) {
        for line in text.split('\n') {
            prints.push_str("print: ");
            prints.push_str(line);
            prints.push('\n');
        }
    }
    eprint!("{prints}");
}

/// Derives once more per named pose, with the pose's attribute values over the user's, and
/// keeps each lot's skeleton as that named pose of the model's skeleton: the GLB writes them as
/// animations.
fn add_named_poses(
    program: &shapegram_eval::Program,
    lots: &[shapegram_eval::InitialShape],
    options: &DeriveOptions,
    named_poses: &[(String, Vec<(String, Value)>)],
    sources: &[SourceFile],
    model: &mut Model,
) -> Result<(), Failure> {
    for (name, overrides) in named_poses {
        let mut posed_options = options.clone();
        posed_options
            .attrs
            .retain(|(attr, _)| !overrides.iter().any(|(a, _)| a == attr));
        posed_options.attrs.extend(overrides.iter().cloned());
        let derivation = shapegram_eval::derive(program, lots, &posed_options).map_err(|e| {
            if e.to_diagnostic().is_some() {
                eprintln!("in the pose '{name}':");
                derive_failure(sources, &e)
            } else {
                Failure::new(format!(
                    "in the pose '{name}': {}",
                    e.message.replace('\n', " ")
                ))
                .with_hints(e.hints.clone())
            }
        })?;
        let posed = derivation.to_model();
        let changed =
            |why: String| Failure::new(format!("the pose '{name}' changes the skeleton ({why})"));
        if posed.skeletons.len() != model.skeletons.len() {
            return Err(changed(format!(
                "{} skeletons instead of {}",
                posed.skeletons.len(),
                model.skeletons.len()
            )));
        }
        for (index, (skeleton, posed)) in
            model.skeletons.iter_mut().zip(&posed.skeletons).enumerate()
        {
            skeleton
                .add_named_pose(name, posed)
                .map_err(|why| changed(format!("skeleton {index}: {why}")))?;
        }
    }
    Ok(())
}

/// What `--metadata` cannot go into, said when it is asked for: it is written into a GLB
/// (glTF node extras) and into tiles (a property table per tile), not into OBJ or STL files.
fn unwritten_metadata(args: &DeriveArgs, glb: bool) -> Option<String> {
    if !args.metadata {
        return None;
    }
    let target = match (&args.output, &args.tiles) {
        (Some(output), _) if !glb => format!("{} is written without it", output.display()),
        (Some(_), _) | (None, Some(_)) => return None,
        (None, None) => "nothing is written".to_owned(),
    };
    Some(format!(
        "--metadata applies to a GLB (-o) and to tiles (--tiles); {target}"
    ))
}

/// `--library` and the repository's options are for goal grammars only.
fn check_goal_options(source: &SourceFile, goal: bool, args: &DeriveArgs) -> Result<(), Failure> {
    if goal {
        if args.style.is_some() {
            return Err(Failure::usage(format!(
                "{} is a goal grammar: --style picks a style of a CGA grammar",
                source.name()
            )));
        }
        return Ok(());
    }
    let option = if !args.library.is_empty() {
        "--library gives goal grammars their rules"
    } else if args.repo.is_some() || args.link.is_some() || args.update || args.offline {
        "--repo, --link, --update and --offline find rules for goal grammars"
    } else {
        return Ok(());
    };
    Err(
        Failure::new(format!("{} is not a goal grammar: {option}", source.name())).with_hints(
            vec![
                "goal grammars have axioms and rules like `fulfills(chair) --> …` (docs/goals.md)"
                    .to_owned(),
            ],
        ),
    )
}

/// Prints a derivation error against the grammar file it has a place in; otherwise the
/// failure carries the message and hints.
fn derive_failure(sources: &[SourceFile], error: &DeriveError) -> Failure {
    let source = error
        .file
        .and_then(|i| sources.get(i))
        .unwrap_or(&sources[0]);
    match error.to_diagnostic() {
        Some(diagnostic) => {
            eprint!("{}", source.render(&diagnostic));
            Failure::reported()
        }
        None => Failure::new(error.message.replace('\n', " ")).with_hints(error.hints.clone()),
    }
}

/// `8.4 ms`, or `2.31 s` from one second on.
pub fn duration(d: Duration) -> String {
    let ms = d.as_secs_f64() * 1e3;
    if ms < 1000.0 {
        format!("{ms:.1} ms")
    } else {
        format!("{:.2} s", ms / 1e3)
    }
}

/// Milliseconds rounded to microseconds, for JSON.
pub fn millis(d: Duration) -> f64 {
    (d.as_secs_f64() * 1e6).round() / 1e3
}

/// The JSON object of `--stats`; field order is output order.
#[derive(Serialize)]
struct StatsJson<'a> {
    grammar: &'a str,
    lots: usize,
    seed: u64,
    shapes: usize,
    leaves: usize,
    faces: usize,
    triangles: usize,
    derive_ms: f64,
    export_ms: f64,
    rules: Ordered<usize>,
    reports: Ordered<ReportSummary>,
    /// The reports as CityEngine's PRT summarises them: `key_n`, `key_sum`, `key_avg`,
    /// `key_min`, `key_max`.
    prt_reports: Ordered<SummaryValue>,
    /// Only for grammars that build skeletons.
    #[serde(skip_serializing_if = "Option::is_none")]
    skeleton: Option<SkeletonJson>,
    /// The grammar's named poses (`@Pose`), only when it has some.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    named_poses: Vec<String>,
    /// The node of `--at-node`, whose state `faces` and `triangles` count; only when given.
    #[serde(skip_serializing_if = "Option::is_none")]
    at_node: Option<usize>,
    /// Goal grammars only.
    #[serde(skip_serializing_if = "Option::is_none")]
    goals: Option<GoalsJson>,
    /// Goal grammars derived with a repository only.
    #[serde(skip_serializing_if = "Option::is_none")]
    repository: Option<resolve::Report>,
}

/// What `--stats` says of a goal grammar's derivation: its steps, the rules and grammars it
/// used (and, by grammar, the steps each took), and the leaves' tags and open goals with how
/// many leaves have each.
#[derive(Serialize)]
struct GoalsJson {
    steps: usize,
    rules_used: usize,
    rules: usize,
    grammars_used: usize,
    grammars: Ordered<usize>,
    tags: Ordered<usize>,
    open_goals: Ordered<usize>,
}

impl GoalsJson {
    fn of(derivation: &Derivation) -> Option<Self> {
        let stats = &derivation.stats;
        if stats.grammars.is_empty() {
            return None;
        }
        let mut grammars = Ordered::default();
        for (name, n) in &stats.grammars {
            *grammars.entry(name) += n;
        }
        let mut tags = Ordered::default();
        let mut open_goals = Ordered::default();
        for semantics in derivation
            .leaves
            .iter()
            .filter_map(|l| l.semantics().map(|s| &**s))
        {
            for tag in &semantics.tags {
                *tags.entry(tag) += 1;
            }
            for goal in &semantics.goals {
                *open_goals.entry(goal) += 1;
            }
        }
        Some(Self {
            steps: stats.steps,
            rules_used: stats.rules.iter().filter(|(_, n)| *n > 0).count(),
            rules: stats.rules.len(),
            grammars_used: stats.grammars.iter().filter(|(_, n)| *n > 0).count(),
            grammars,
            tags,
            open_goals,
        })
    }
}

/// The skeletons' counts in `--stats`: sections, the joints linking them to a parent, and the
/// joints whose limits let them move.
#[derive(Serialize)]
struct SkeletonJson {
    skeletons: usize,
    sections: usize,
    joints: usize,
    free_joints: usize,
}

impl SkeletonJson {
    fn of(model: &Model) -> Option<Self> {
        if model.skeletons.is_empty() {
            return None;
        }
        let sections = model.skeletons.iter().map(|s| s.len()).sum();
        let free_joints = model
            .skeletons
            .iter()
            .flat_map(|s| s.sections())
            .filter(|(_, s)| s.limits().is_free())
            .count();
        Some(Self {
            skeletons: model.skeletons.len(),
            sections,
            joints: sections - model.skeletons.len(),
            free_joints,
        })
    }
}

impl<'a> StatsJson<'a> {
    fn new(
        grammar: &'a str,
        lots: usize,
        seed: u64,
        derivation: &Derivation,
        model: &Model,
        derive_time: Duration,
        export_time: Duration,
    ) -> Self {
        let mut rules = Ordered::default();
        for (name, n) in &derivation.stats.rules {
            // Rules of one name with different parameter counts are counted together.
            *rules.entry(name) += n;
        }
        let mut reports: Ordered<ReportSummary> = Ordered::default();
        for (key, value) in &derivation.reports {
            reports.entry(key).add(value);
        }
        let mut prt_reports: Ordered<SummaryValue> = Ordered::default();
        for (key, value) in shapegram_eval::summarise_reports(&derivation.reports) {
            *prt_reports.entry(&key) = match value {
                Value::Number(n) => SummaryValue::Number(n),
                other => SummaryValue::Text(other.to_string()),
            };
        }
        Self {
            grammar,
            lots,
            seed,
            shapes: derivation.stats.shapes,
            leaves: derivation.stats.leaves,
            faces: model.parts.iter().map(|p| p.mesh.face_count()).sum(),
            triangles: model.parts.iter().map(|p| p.mesh.triangulate().len()).sum(),
            derive_ms: millis(derive_time),
            export_ms: millis(export_time),
            rules,
            reports,
            prt_reports,
            skeleton: SkeletonJson::of(model),
            named_poses: Vec::new(),
            at_node: None,
            goals: GoalsJson::of(derivation),
            repository: None,
        }
    }
}

/// A JSON object whose keys keep their order of insertion.
struct Ordered<V> {
    entries: Vec<(String, V)>,
    index: HashMap<String, usize>,
}

impl<V> Default for Ordered<V> {
    fn default() -> Self {
        Self {
            entries: Vec::new(),
            index: HashMap::new(),
        }
    }
}

impl<V: Default> Ordered<V> {
    fn entry(&mut self, key: &str) -> &mut V {
        let i = match self.index.get(key) {
            Some(&i) => i,
            None => {
                self.entries.push((key.to_owned(), V::default()));
                self.index.insert(key.to_owned(), self.entries.len() - 1);
                self.entries.len() - 1
            }
        };
        &mut self.entries[i].1
    }
}

impl<V: Serialize> Serialize for Ordered<V> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.entries.len()))?;
        for (key, value) in &self.entries {
            map.serialize_entry(key, value)?;
        }
        map.end()
    }
}

/// One entry of PRT's report summary: a number, or for string reports a string.
#[derive(Default, Serialize)]
#[serde(untagged)]
enum SummaryValue {
    #[default]
    None,
    Number(f64),
    Text(String),
}

/// The values reported under one key: how many, and sum, min and max of the numeric ones.
#[derive(Default, Serialize)]
struct ReportSummary {
    count: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    sum: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    min: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    max: Option<f64>,
}

impl ReportSummary {
    fn add(&mut self, value: &Value) {
        self.count += 1;
        if let Value::Number(n) = *value {
            self.sum = Some(self.sum.unwrap_or(0.0) + n);
            self.min = Some(self.min.map_or(n, |m| m.min(n)));
            self.max = Some(self.max.map_or(n, |m| m.max(n)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_read_in_milliseconds_then_seconds() {
        assert_eq!(duration(Duration::from_micros(8_420)), "8.4 ms");
        assert_eq!(duration(Duration::from_millis(2_314)), "2.31 s");
        assert_eq!(millis(Duration::from_nanos(1_234_567)), 1.235);
    }

    #[test]
    fn ordered_maps_keep_first_appearance_and_reports_summarise_numbers() {
        let mut reports: Ordered<ReportSummary> = Ordered::default();
        for (key, value) in [
            ("zeta", Value::Number(2.0)),
            ("alpha", Value::string("x")),
            ("zeta", Value::Number(-1.5)),
            ("zeta", Value::Number(4.0)),
        ] {
            reports.entry(key).add(&value);
        }
        assert_eq!(
            serde_json::to_string(&reports).unwrap(),
            r#"{"zeta":{"count":3,"sum":4.5,"min":-1.5,"max":4.0},"alpha":{"count":1}}"#
        );
    }
}
