-- SPDX-License-Identifier: BSD-3-Clause
-- wsgsim's own test script in the dialect of UMI's gripper script
-- (docs/scripting.md, "The two dialects"): 0xB0 query, 0xB1 PD step; a
-- dummy byte, floats from payload[2]; the reply is the status, the low
-- byte of the system flags and four floats (17 bytes after the status).
require "socket"

cmd.register(0xB0)
cmd.register(0xB1)

local function float_at(payload, k)
    return bton({payload[k], payload[k + 1], payload[k + 2], payload[k + 3]})
end

local function pd_step(payload)
    local target, target_speed = float_at(payload, 2), float_at(payload, 6)
    local kp, kd = float_at(payload, 10), float_at(payload, 14)
    local travel_force, blocked_force = float_at(payload, 18), float_at(payload, 22)
    mc.speed(kp * (target - mc.position()) + kd * (target_speed - mc.speed()))
    if mc.blocked() then
        mc.force(blocked_force)
    else
        mc.force(travel_force)
    end
end

local function serve()
    local id, payload = cmd.read()
    if id == 0xB1 then
        pd_step(payload)
    end
    -- uses the global socket that require "socket" sets
    cmd.send(id, etob(E_SUCCESS), gripper.state() % 256, ntob(mc.position()),
             ntob(mc.speed()), ntob(mc.aforce()), ntob(socket.gettime()))
end

while true do
    if cmd.online() then
        local ok, err = pcall(serve)
        if not ok then
            print("error: " .. tostring(err))
            sleep(100)
        end
    else
        sleep(100)
    end
end
