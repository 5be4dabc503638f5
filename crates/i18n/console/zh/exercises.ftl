# 某次训练各项目的结果。

exercises-ended = 已结束
exercises-running = 仍在进行中
exercises-heading = { $when } 的训练，逐项结果
exercises-back = 返回进展页面
exercises-none = 没有逐项结果：运行本次训练的训练站版本较旧，或训练未正常结束。
exercises-column = { $n }. { $name }
exercises-time-cell = { $active } / { $prescribed }
exercises-caption = 各训练项目自己的结果；整次训练的合计见进展页面。
exercises-col-result = 结果
exercises-time-row = 时间：实际活动 / 处方（秒）
exercises-sweep-spring = 触觉扫描：本级别的弹簧刚度
exercises-sweep-damper = 触觉扫描：本级别的阻尼
exercises-sweep-inertia = 触觉扫描：本级别附加的重量（惯量）
exercises-sweep-frequency = 触觉扫描：本级别转盘的运动速度（频率）
