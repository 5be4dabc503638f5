# Captions of the pictures (crates/station/src/render/pictures). Each is also spoken.
# One idea each, at most 12 words, everyday words.
picture-road-winding = Turn the wheel left and right along the road.
picture-road-straight = Keep the car in the middle of the road.
picture-road-zigzag = Follow the zigzag road with the wheel.
picture-road-tightening = The bend gets tighter. Turn a little more.
picture-road-sharp-turns = Steer around the sharp corners.
picture-road-s-bend = Steer through the S-shaped bend.
picture-road-lane-change = Move into the other lane. Then stay there.
picture-road-slalom = Steer between the cones.
picture-dial = Turn the wheel. The black needle follows the red one.
picture-strength = Push the wheel hard. It will not move.
picture-rest = Rest now. Take your hands off the wheel.
picture-pause = Paused. Take your time.
picture-buttons = Press a button on the wheel.
picture-wheel-turn = Turn the wheel to choose. Then press a button.
picture-plug = Plug the wheel back in.
picture-arm-sensor-plug = Plug the arm sensor back in.
picture-yes = Yes
picture-no = No
picture-done = Well done. That is all for today.
picture-today = Your exercises for today.
