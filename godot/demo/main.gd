extends Node3D
## The thesis's demo: three houses of one grammar side by side. Enter gives them new seeds
## (derived in the background, so no frame waits on them); WASD moves, the mouse turns the
## camera while the right button is held; Esc quits.

const SPEED := 12.0
const TURN := 0.003

@onready var camera: Camera3D = $Camera


## The three houses' nodes.
func houses() -> Array[GrammarInstance3D]:
	return [$HouseA, $HouseB, $HouseC]


## Gives every house a new random seed; each derives again on its own thread.
func reseed() -> void:
	for house in houses():
		house.grammar_state.seed = randi()


func _unhandled_input(event: InputEvent) -> void:
	if event is InputEventKey and event.pressed and not event.echo:
		match event.keycode:
			KEY_ENTER, KEY_KP_ENTER:
				reseed()
			KEY_ESCAPE:
				get_tree().quit()
	elif event is InputEventMouseMotion and Input.is_mouse_button_pressed(MOUSE_BUTTON_RIGHT):
		camera.rotate_y(-event.relative.x * TURN)
		camera.rotate_object_local(Vector3.RIGHT, -event.relative.y * TURN)


func _process(delta: float) -> void:
	var move := Vector3(
		float(Input.is_key_pressed(KEY_D)) - float(Input.is_key_pressed(KEY_A)),
		0.0,
		float(Input.is_key_pressed(KEY_S)) - float(Input.is_key_pressed(KEY_W)))
	camera.translate(move * SPEED * delta)
