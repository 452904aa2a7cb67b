extends SceneTree
## The extension tested headless (`.ci/run`): loads the demo scene, waits for its three houses,
## gives them new seeds ROUNDS times and lets them derive in the background, checks every
## GrammarMesh's vertex count against the runtime's for the same grammar and seed, then does
## the same with the derivation on the main thread, and prints the longest frame of each; then
## presses Enter as a player would and checks the houses got new seeds and meshes.
## The runtime's counts come as user arguments `FILE:SEED=VERTICES` (crates/shapegram-godot's
## counts example). Exits with 1 when a check fails.

const ROUNDS := 10
const FIRST_SEED := 100
## Frames to wait for one round at most (a derivation takes milliseconds).
const PATIENCE := 100000

var expected := {}
var houses: Array[GrammarInstance3D] = []
var failures := 0
var phase := "initial"
var round_index := 0
var waited := 0
var last_usec := 0
## Which houses' states emitted `changed` since they were given their seeds.
var arrived: Array[bool] = [false, false, false]
## The frames' lengths in microseconds while regenerating, in each mode.
var frames := {"background": [], "main thread": []}


func _initialize() -> void:
	for argument in OS.get_cmdline_user_args():
		var pair := argument.split("=")
		expected[pair[0]] = int(pair[1])
	var main: Node = load("res://main.tscn").instantiate()
	root.add_child(main)
	houses.assign(main.houses())
	for i in houses.size():
		houses[i].grammar_state.changed.connect(func() -> void: arrived[i] = true)
	check_errors()
	check_cga()
	check_textured()
	check_saved(main)


func _process(_delta: float) -> bool:
	var now := Time.get_ticks_usec()
	var frame := now - last_usec if last_usec > 0 else 0
	last_usec = now
	if phase in frames:
		frames[phase].append(frame)
	waited += 1
	if waited > PATIENCE:
		fail("round %d (%s) never finished" % [round_index, phase])
		return finish()
	if not settled():
		return false
	waited = 0
	if phase == "enter":
		check_enter()
		return finish()
	check_round()
	if phase == "initial":
		phase = "background"
	elif round_index == ROUNDS - 1:
		if phase == "main thread":
			press_enter()
			return false
		phase = "main thread"
		round_index = 0
		for house in houses:
			house.grammar_state.background = false
	else:
		round_index += 1
	reseed()
	return false


## Whether every house has the derivation for the seed it has now.
func settled() -> bool:
	for i in houses.size():
		if not arrived[i] or houses[i].grammar_state.is_generating():
			return false
	return true


## Seeds no round used before.
func reseed() -> void:
	for i in houses.size():
		arrived[i] = false
		houses[i].grammar_state.seed = FIRST_SEED + 3 * round_index + i


func check_round() -> void:
	for house in houses:
		var state := house.grammar_state
		var key := "%s:%d" % [state.grammar_file.get_file(), state.seed]
		var vertices: int = house.grammar_mesh().vertex_count()
		if not expected.has(key):
			fail("no expected count for %s" % key)
		elif vertices != expected[key] or state.vertex_count() != vertices:
			fail("%s: the mesh has %d vertices, the state %d, the runtime %d" % [key, vertices, state.vertex_count(), expected[key]])
		var parts := state.part_names()
		if house.mesh.get_surface_count() != parts.size() or parts.is_empty():
			fail("%s: %d surfaces for %d parts" % [key, house.mesh.get_surface_count(), parts.size()])
		elif house.mesh.surface_get_name(0) != parts[0]:
			fail("%s: the first surface is named %s, not %s" % [key, house.mesh.surface_get_name(0), parts[0]])


## The demo's Enter, as a player presses it: every house gets a new random seed.
func press_enter() -> void:
	phase = "enter"
	for i in houses.size():
		arrived[i] = false
		houses[i].set_meta("old_seed", houses[i].grammar_state.seed)
	var key := InputEventKey.new()
	key.keycode = KEY_ENTER
	key.pressed = true
	root.push_input(key)


func check_enter() -> void:
	for house in houses:
		var state := house.grammar_state
		if state.seed == house.get_meta("old_seed"):
			fail("Enter left %s's seed at %d" % [house.name, state.seed])
		if house.grammar_mesh().vertex_count() != state.vertex_count():
			fail("after Enter, %s's mesh has %d vertices, its state %d" % [house.name, house.grammar_mesh().vertex_count(), state.vertex_count()])
	print("Enter: new seeds %s" % ", ".join(houses.map(func(h: GrammarInstance3D) -> String: return str(h.grammar_state.seed))))


## A saved scene keeps the houses' states, not their triangles (the meshes are made again).
func check_saved(main: Node) -> void:
	var packed := PackedScene.new()
	packed.pack(main)
	var path := "user://saved.tscn"
	if ResourceSaver.save(packed, path) != OK:
		fail("the scene cannot be saved")
		return
	var text := FileAccess.get_file_as_string(path)
	if text.count("type=\"GrammarState\"") != 3 or "ArrayMesh" in text or "GrammarMesh" in text or "_surfaces" in text:
		fail("the saved scene is not three states without meshes:\n%s" % text)
	var loaded: Node = load(path).instantiate()
	if not loaded.get_node("HouseA").grammar_mesh() is GrammarMesh:
		fail("the loaded scene's house shows no GrammarMesh")
	loaded.free()


## A CGA grammar with attributes, derived on the main thread.
func check_cga() -> void:
	var state := GrammarState.new()
	state.auto_generate = false
	state.grammar_file = "res://grammars/house.cga"
	state.seed = 1
	var mesh := GrammarMesh.new()
	mesh.state = state
	if not state.generate():
		fail("house.cga: %s" % state.last_error)
	elif mesh.vertex_count() != expected.get("house.cga:1", -1):
		fail("house.cga: %d vertices, the runtime %d" % [mesh.vertex_count(), expected.get("house.cga:1", -1)])
	state.attributes = {"storeys": 3}
	if not state.generate() or mesh.vertex_count() <= expected.get("house.cga:1", 0):
		fail("house.cga with 3 storeys: %d vertices (%s)" % [mesh.vertex_count(), state.last_error])
	print("house.cga: %d vertices with 3 storeys, %d surfaces" % [mesh.vertex_count(), mesh.get_surface_count()])


## A textured grammar: its textured parts' surfaces have uvs and their image as the albedo
## texture, at the image's size; the others neither.
func check_textured() -> void:
	var state := GrammarState.new()
	state.auto_generate = false
	state.grammar_file = "res://grammars/textured_house.cga"
	var mesh := GrammarMesh.new()
	mesh.state = state
	if not state.generate():
		fail("textured_house.cga: %s" % state.last_error)
		return
	var sizes := {}
	for path in ["brick", "tiles"]:
		var image := Image.load_from_file("res://grammars/textures/%s.png" % path)
		sizes[image.get_size()] = path
	var textured := []
	for surface in mesh.get_surface_count():
		var arrays := mesh.surface_get_arrays(surface)
		var uvs = arrays[Mesh.ARRAY_TEX_UV]
		var material: StandardMaterial3D = mesh.surface_get_material(surface)
		var texture := material.albedo_texture
		if texture == null:
			if uvs != null and uvs.size() > 0:
				fail("surface %d has uvs but no texture" % surface)
			continue
		if uvs == null or uvs.size() != mesh.surface_get_array_len(surface):
			fail("textured surface %d has no uv per vertex" % surface)
		var size := Vector2i(texture.get_size())
		if size not in sizes:
			fail("surface %d's texture is %s, no image's size" % [surface, size])
		textured.append(sizes.get(size, "?"))
		var named: String = {"brick": "brick", "tiles": "roof_tiles"}.get(sizes.get(size, "?"), "?")
		if material.resource_name != named:
			fail("surface %d's material is called %s, not %s" % [surface, material.resource_name, named])
	textured.sort()
	if textured != ["brick", "tiles"]:
		fail("textured surfaces: %s" % [textured])
	print("textured_house.cga: %d surfaces, textured with %s" % [mesh.get_surface_count(), ", ".join(textured)])


## Bad input: errors with their place, the last mesh kept, no crash.
func check_errors() -> void:
	var state := GrammarState.new()
	state.auto_generate = false
	state.grammar_text = "Lot --> extrude("
	if state.generate() or "grammar:1:17" not in state.last_error:
		fail("a broken grammar: %s" % state.last_error)
	state.grammar_text = ""
	state.grammar_file = "res://grammars/house.cga"
	state.attributes = {"storeys": "three"}
	if state.generate() or "storeys" not in state.last_error:
		fail("a string for a number: %s" % state.last_error)
	state.attributes = {"storeys": 2}
	if not state.generate() or state.last_error != "":
		fail("house.cga after the errors: %s" % state.last_error)
	var kept := state.vertex_count()
	state.attributes = {"nosuch": 1}
	if state.generate() or state.vertex_count() != kept:
		fail("an unknown attribute: %s, %d vertices kept of %d" % [state.last_error, state.vertex_count(), kept])
	state.grammar_file = "res://grammars/missing.cga"
	if state.generate() or "missing.cga" not in state.last_error:
		fail("a missing file: %s" % state.last_error)


func fail(message: String) -> void:
	printerr("FAIL: ", message)
	failures += 1


func finish() -> bool:
	for mode in frames:
		var lengths: Array = frames[mode]
		lengths.sort()
		print("regenerating three houses %d times on the %s: longest frame %.2f ms, median %.3f ms, %d frames" % [ROUNDS, mode, lengths.back() / 1000.0, lengths[lengths.size() / 2] / 1000.0, lengths.size()])
	# A headless Godot cannot draw, so it sleeps this long after every frame: a frame with
	# nothing to do lasts that long, and what a frame takes beyond it is work.
	print("sleep after every frame: %.3f ms" % (OS.low_processor_usage_mode_sleep_usec / 1000.0))
	print("checks failed: %d" % failures)
	quit(1 if failures > 0 else 0)
	return true
