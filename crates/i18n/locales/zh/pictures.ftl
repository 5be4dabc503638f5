# 图片说明（crates/station/src/render/pictures），每一句也会读出来。
picture-road-winding = 沿着路左右转动方向盘。
picture-road-straight = 让车保持在路中间。
picture-road-zigzag = 用方向盘沿着之字形的路走。
picture-road-tightening = 弯越来越急。多转一点。
picture-road-sharp-turns = 转过急弯。
picture-road-s-bend = 开过S形弯道。
picture-road-lane-change = 换到另一条车道。然后保持住。
picture-road-slalom = 在锥桶之间绕行。
picture-dial = 转动方向盘。让黑针跟着红针。
picture-strength = 用力推方向盘。它不会动。
picture-rest = 现在休息。手离开方向盘。
picture-pause = 已暂停。慢慢来。
picture-buttons = 按方向盘上的一个按钮。
picture-yes = 是
picture-no = 否
picture-done = 做得好。今天就到这里。
picture-today = 您今天的练习。
