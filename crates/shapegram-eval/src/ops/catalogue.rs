//! Every CGA operation by name: implemented, accepted without effect, or not supported yet,
//! with the signatures editors show.

/// Operations that would only change texturing or shading: accepted without effect.
pub(super) const VISUAL_ONLY: &[&str] = &[
    "softenNormals",
    "setNormals",
    "cleanupGeom",
    "resetMaterial",
    "annotation",
];

/// CGA operations that are recognised but not implemented yet.
pub(super) const UNSUPPORTED: &[&str] = &[
    "rectify",
    "modify",
    "insertAlongUV",
    "reduceGeometry",
    "setTagsFromEdgeAttrs",
];

/// The operations [`compile`] builds, besides the visual-only and unsupported ones.
pub(super) const IMPLEMENTED: &[&str] = &[
    "setupProjection",
    "projectUV",
    "texture",
    "tileUV",
    "scaleUV",
    "translateUV",
    "offsetUV",
    "rotateUV",
    "deleteUV",
    "copyUV",
    "normalizeUV",
    "extrude",
    "t",
    "r",
    "s",
    "center",
    "mirror",
    "alignScopeToAxes",
    "rotateScope",
    "mirrorScope",
    "setPivot",
    "resetGeometry",
    "i",
    "insert",
    "primitiveCube",
    "primitiveQuad",
    "primitiveDisk",
    "primitivePyramid",
    "primitiveCylinder",
    "primitiveCone",
    "primitiveSphere",
    "split",
    "splitArea",
    "splitAndSetbackPerimeter",
    "comp",
    "color",
    "set",
    "report",
    "print",
    "reverseNormals",
    "trim",
    "convexify",
    "scatter",
    "translate",
    "rotate",
    "footprint",
    "deleteHoles",
    "cleanupGeometry",
    "envelope",
    "innerRectangle",
    "innerRect",
    "offset",
    "roofGable",
    "roofHip",
    "roofPyramid",
    "roofShed",
    "roofRidge",
    "label",
    "tag",
    "deleteTags",
    "snap",
    "Snap",
    "implicit",
    "csg",
    "alignScopeToGeometry",
    "alignScopeToGeometryBBox",
    "setback",
    "setbackPerEdge",
    "setbackToArea",
    "shapeL",
    "shapeU",
    "shapeO",
    "joint",
    "rotationLimits",
    "translationLimits",
    "rotateJoint",
    "translateJoint",
    "taper",
    "twist",
    "shear",
    "sync",
    "union",
    "subtract",
    "intersect",
    "inline",
];

/// The signature of each operation [`compile`] builds, as hints and the studio show it.
const SIGNATURES: &[(&str, &str)] = &[
    ("extrude", "extrude([world.up | face.normal,] distance)"),
    ("t", "t(x, y, z)"),
    ("r", "r([scopeCenter,] x, y, z)"),
    ("s", "s(x, y, z)"),
    ("center", "center(xyz)"),
    ("mirror", "mirror(x, y, z)"),
    (
        "alignScopeToAxes",
        "alignScopeToAxes([x | y | z | world.xyz])",
    ),
    ("rotateScope", "rotateScope(x, y, z)"),
    ("mirrorScope", "mirrorScope(xFlip, yFlip, zFlip)"),
    ("setPivot", "setPivot(xyz | yzx | zxy, cornerIndex)"),
    ("resetGeometry", "resetGeometry()"),
    (
        "i",
        "i(path [, yUp | zUp [, alignSizeAndPosition | keepSizeAndPosition | keepSizeAlignPosition [, numericalCleanup | noCleanup]]])",
    ),
    (
        "insert",
        "i(path [, yUp | zUp [, alignSizeAndPosition | keepSizeAndPosition | keepSizeAlignPosition [, numericalCleanup | noCleanup]]])",
    ),
    (
        "primitiveCube",
        "primitiveCube() | primitiveCube(width, height, depth)",
    ),
    (
        "primitiveQuad",
        "primitiveQuad() | primitiveQuad(width, length)",
    ),
    (
        "primitiveDisk",
        "primitiveDisk() | primitiveDisk(nVertices) | primitiveDisk(nVertices, radius)",
    ),
    ("primitivePyramid", "primitivePyramid()"),
    (
        "primitiveCylinder",
        "primitiveCylinder([nSides]) | primitiveCylinder(nSides, radius, height)",
    ),
    ("primitiveCone", "primitiveCone([nSides])"),
    ("primitiveSphere", "primitiveSphere([nRows [, nColumns]])"),
    (
        "split",
        "split(x | y | z [, adjust | noAdjust] [, sequential | parallel] [, snap [, \"tag\"]]) { … } | split(u | v, uvSpace | unitSpace, uvSet) { … }",
    ),
    (
        "splitArea",
        "splitArea(x | y | z [, adjust | noAdjust]) { area : … | … }",
    ),
    (
        "splitAndSetbackPerimeter",
        "splitAndSetbackPerimeter(offset [, firstEdge, edgeMask[]]) { length : depth : … | … }[*] { remainder : … }",
    ),
    ("comp", "comp(f | e | fe | v | fv | h) { … }"),
    ("color", "color(\"#rrggbb\") | color(r, g, b)"),
    ("set", "set(attribute, value)"),
    ("report", "report(key, value)"),
    ("print", "print(value)"),
    ("reverseNormals", "reverseNormals()"),
    ("trim", "trim()"),
    ("convexify", "convexify([maxCutLength])"),
    (
        "translate",
        "translate(abs | rel, scope | pivot | object | world, x, y, z)",
    ),
    (
        "rotate",
        "rotate(abs | rel, scope | pivot | object | world, xAngle, yAngle, zAngle)",
    ),
    (
        "scatter",
        "scatter(surface | volume | scope, n, uniform | gaussian [, center | front | back | left | right | top | bottom [, stddev]]) { … }",
    ),
    ("footprint", "footprint()"),
    ("deleteHoles", "deleteHoles()"),
    (
        "cleanupGeometry",
        "cleanupGeometry(vertices | edges | faces | all, tolerance)",
    ),
    (
        "envelope",
        "envelope(normal | world.up, maxHeight, frontBase, frontAngle [, backBase, backAngle [, sideBase, sideAngle | rightBase, rightAngle, leftBase, leftAngle]]) | envelope(normal | world.up, maxHeight, baseHeights[], angles[])",
    ),
    (
        "innerRectangle",
        "innerRectangle(scope | edge) { shape : … | remainder : … }",
    ),
    ("innerRect", "innerRect()"),
    ("offset", "offset(distance [, inside | border])"),
    (
        "roofGable",
        "roofGable([byAngle | byHeight,] value [, overhangX [, overhangY [, even [, edgeIndex]]]])",
    ),
    (
        "roofHip",
        "roofHip([byAngle | byHeight,] value [, overhang [, even]])",
    ),
    ("roofPyramid", "roofPyramid([byAngle | byHeight,] value)"),
    (
        "roofShed",
        "roofShed([byAngle | byHeight,] value [, edgeIndex])",
    ),
    ("roofRidge", "roofRidge([byAngle | byHeight,] value)"),
    ("label", "label(\"name\")"),
    ("tag", "tag(name [, auto | faces | edges | vertices])"),
    (
        "deleteTags",
        "deleteTags([tagQuery [, all | faces | edges | vertices]])",
    ),
    ("snap", "snap(x | y | z | xy | … [, \"tag\"])"),
    ("Snap", "snap(x | y | z | xy | … [, \"tag\"])"),
    (
        "implicit",
        "implicit(box | sphere | cylinder | cone | pyramid | torus | capsule | \"file.cave\")",
    ),
    (
        "csg",
        "csg(\"group\", union | subtract | intersect [, fillet]) | csg(\"group\", morph, amount)",
    ),
    (
        "alignScopeToGeometry",
        "alignScopeToGeometry(yUp | zUp, [faceIndex | world.lowest | largest | any,] edgeIndex | world.lowest | longest)",
    ),
    (
        "alignScopeToGeometryBBox",
        "alignScopeToGeometryBBox(xy | yx | xz | zx | yz | zy)",
    ),
    (
        "setback",
        "setback(distance) { selector : … | remainder : … }",
    ),
    (
        "setbackPerEdge",
        "setbackPerEdge(distance [, uvSet]) { selector : … | remainder : … }",
    ),
    (
        "setbackToArea",
        "setbackToArea(area [, minDistances[] [, maxDistances[]]] [, uvSet]) { selector : … | remainder : … }",
    ),
    ("shapeL", "shapeL(frontDepth, leftWidth)"),
    ("shapeU", "shapeU(frontDepth, rightWidth, leftWidth)"),
    (
        "shapeO",
        "shapeO(frontDepth, rightWidth, backDepth, leftWidth)",
    ),
    ("joint", "joint(x, y, z)"),
    ("rotationLimits", "rotationLimits(x | y | z, min, max)"),
    (
        "translationLimits",
        "translationLimits(x | y | z, min, max)",
    ),
    ("rotateJoint", "rotateJoint(x, y, z)"),
    ("translateJoint", "translateJoint(x, y, z)"),
    ("taper", "taper(x | y | z, factor) | taper(height)"),
    ("twist", "twist(x | y | z, degrees)"),
    ("shear", "shear(x | y | z, toward x | y | z, amount)"),
    ("sync", "sync(synchronization)"),
    (
        "setupProjection",
        "setupProjection(uvSet, scope.xy, width, height [, widthOffset, heightOffset [, uwFactor]])",
    ),
    ("projectUV", "projectUV(uvSet)"),
    ("texture", "texture(path)"),
    ("tileUV", "tileUV(uvSet, width, height)"),
    ("scaleUV", "scaleUV(uvSet, uFactor, vFactor)"),
    ("translateUV", "translateUV(uvSet, u, v)"),
    ("offsetUV", "translateUV(uvSet, u, v)"),
    ("rotateUV", "rotateUV(uvSet, degrees)"),
    ("deleteUV", "deleteUV(uvSet)"),
    ("copyUV", "copyUV(fromSet, toSet)"),
    (
        "normalizeUV",
        "normalizeUV(uvSet, uv | uvUniform | u | v, separatePerFace | collectiveAllFaces)",
    ),
    (
        "union",
        "union([swap | noSwap]) Rule | union { ops } | union { opsA | opsB }",
    ),
    (
        "subtract",
        "subtract([swap | noSwap]) Rule | subtract { ops } | subtract { opsA | opsB }",
    ),
    (
        "intersect",
        "intersect([swap | noSwap]) Rule | intersect { ops } | intersect { opsA | opsB }",
    ),
    (
        "inline",
        "inline([append | unify | recompose]) Rule | inline([append | unify | recompose]) { ops }",
    ),
];

/// The signature of an implemented operation.
pub(crate) fn signature(name: &str) -> Option<&'static str> {
    SIGNATURES.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
}

/// How far the engine supports an operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Support {
    /// Built and run.
    Implemented,
    /// Accepted without effect: it would change only texturing or shading.
    VisualOnly,
    /// Recognised, skipped with a warning.
    Unsupported,
}

/// Every operation the engine knows, with its support and, when implemented, its signature.
pub fn operations() -> impl Iterator<Item = (&'static str, Support, Option<&'static str>)> {
    let implemented = IMPLEMENTED
        .iter()
        .map(|n| (*n, Support::Implemented, signature(n)));
    let visual = VISUAL_ONLY.iter().map(|n| (*n, Support::VisualOnly, None));
    let unsupported = UNSUPPORTED.iter().map(|n| (*n, Support::Unsupported, None));
    implemented.chain(visual).chain(unsupported)
}

/// Whether an operation of this name exists (implemented or not).
pub(crate) fn is_operation(name: &str) -> bool {
    IMPLEMENTED.contains(&name) || VISUAL_ONLY.contains(&name) || UNSUPPORTED.contains(&name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_implemented_operation_has_a_signature_named_after_it() {
        for name in IMPLEMENTED {
            let signature = signature(name).unwrap_or_else(|| panic!("no signature for {name}"));
            let shown = match *name {
                "insert" => "i",
                "Snap" => "snap",
                "offsetUV" => "translateUV",
                other => other,
            };
            assert!(
                signature.starts_with(&format!("{shown}(")),
                "{name}: {signature}"
            );
        }
        assert_eq!(SIGNATURES.len(), IMPLEMENTED.len());
        let listed: Vec<_> = operations().collect();
        assert_eq!(
            listed.len(),
            IMPLEMENTED.len() + VISUAL_ONLY.len() + UNSUPPORTED.len()
        );
        assert!(listed.contains(&(
            "extrude",
            Support::Implemented,
            Some("extrude([world.up | face.normal,] distance)")
        )));
    }
}
