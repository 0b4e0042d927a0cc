-- SPDX-License-Identifier: BSD-3-Clause
-- wsgsim's own test script in the dialect of wsg50-ros-pkg's gripper
-- script (docs/scripting.md, "The two dialects"): 9-byte requests (dummy
-- byte, width, speed) with IDs 0xB0 measure, 0xB1 position, 0xB2 speed; a
-- 23-byte reply with the forces of two FMF fingers. A finger slot it did
-- not count has no force (nil, as math.nan is on the device): ntob raises,
-- the request is never answered.
cmd.register(0xB0)
cmd.register(0xB1)
cmd.register(0xB2)

local fmf_fingers = 0
for i = 0, finger.count() - 1 do
    if finger.type(i) ~= "fmf" then
        break
    end
    fmf_fingers = fmf_fingers + 1
end
printf("#FMF fingers: %d\n", fmf_fingers)

local velocity_mode = false
local speed_goal = 0

local function finger_force(i)
    if i < fmf_fingers then
        return finger.data(i)
    end
    return math.nan -- nil: no such constant
end

local function float_at(payload, k)
    return bton({payload[k], payload[k + 1], payload[k + 2], payload[k + 3]})
end

local function serve()
    local id, payload = cmd.read()
    local width, speed = float_at(payload, 2), float_at(payload, 6)
    if id == 0xB1 then
        velocity_mode = false
        if mc.busy() then
            mc.stop()
        end
        mc.move(width, math.abs(speed), 0)
    elseif id == 0xB2 then
        velocity_mode = true
        speed_goal = speed
        mc.speed(speed)
    end
    cmd.send(id, etob(E_SUCCESS), gripper.state() % 256,
             {ntob(mc.position()), ntob(mc.speed()), ntob(mc.aforce()),
              ntob(finger_force(0)), ntob(finger_force(1))})
end

while true do
    if cmd.online() then
        local ok, err = pcall(serve)
        if not ok then
            printf("error: %s\n", tostring(err))
            sleep(100)
        end
        -- velocity mode ends at a block at either end of the stroke
        local pos = mc.position()
        if velocity_mode and mc.blocked() and
            ((speed_goal < 0 and pos < 50) or (speed_goal > 0 and pos > 50)) then
            mc.stop()
            velocity_mode = false
        end
    else
        sleep(100)
    end
end
