# 治疗师给患者的消息。

messages-empty = 消息为空。
messages-too-long = 消息过长：{ $chars } 个字符，最多 { $max } 个。
messages-control = 消息含有换行或其他控制字符：请写在一行内。
messages-sent-at = 发送于 { $when }
messages-not-seen = 尚未查看
messages-seen-at = 查看于 { $when }
messages-none = 尚无消息。
messages-count = { $chars } / { $max } 个字符
messages-label = 给患者的消息，将在其下次训练开始时以大字显示
messages-send = 发送消息
messages-refresh = 刷新
messages-sent = 已发送：患者将在下次训练开始时看到。
messages-heading = 给患者的消息
